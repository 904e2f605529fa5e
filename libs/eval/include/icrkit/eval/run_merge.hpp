#pragma once
/// \file
/// The run folders of the shards of one study (`--shard i/N` of `icrkit
/// evaluate`, `paper` or `sensitivity`) joined into the records, run.json
/// and renders of the unsharded run, as `icrkit merge` writes them
/// (docs/scaling.md). Writing the tables and figures is the report's.

#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/eval/sensitivity_study.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

struct MergedRun {
  std::vector<GraspRecord> records;        ///< every shard's, sorted (dataset, fingers, index)
  std::string run_json;                    ///< the shards' run.json, shard 0/1, "merged_from": the folders
  std::vector<std::string> dataset_order;  ///< run.json's datasets
  std::vector<std::size_t> finger_counts;  ///< run.json's config
  /// The shards' renders an unsharded run makes (the first `renders`
  /// evaluated grasps of each dataset; all of them for runs whose run.json
  /// has no "renders"), to be copied into the merged folder's renders/.
  std::vector<std::string> render_files;
  /// The shards' planned.jsonl and surface.jsonl lines (one per dataset,
  /// from the shard that held its first grasp), in dataset order.
  std::vector<std::string> planned_lines, surface_lines;
  /// A sensitivity study's table, computed from the merged records.
  std::optional<SensitivityTable> sensitivity;
};

/// Reads and checks the run folders: each must have run.json and
/// grasps.jsonl, all the same parameters, datasets and shard count, every
/// shard exactly once, no grasp in two shards. InputError naming the folder
/// or file and what is wrong ("shards missing: 2 of 3", "given twice",
/// "differ"); source "run folders" when no folder is given.
MergedRun mergeRunFolders(const std::vector<std::string>& folders);

}  // namespace icrkit::eval
