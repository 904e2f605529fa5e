#pragma once
/// \file
/// The files of an experiment run directory, all computed from the grasp
/// records (so a merged set of shards gives the same files as one run):
/// grasps.jsonl, table1.{md,csv,json,svg,png}, eligibility.json,
/// fig8_<N>fingers.{svg,png,json} for each finger count,
/// conservative.{json,md,svg} (plain against uncertainty-aware growth, and
/// where the recommended contacts land), run.json.

#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/eval/results_tables.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace icrkit::report {

struct ExperimentOutputs {
  std::vector<std::string> dataset_order;  ///< Table I row order (others follow sorted)
  std::vector<std::size_t> finger_counts;  ///< one Fig. 8 per count
  std::string run_json;                    ///< written verbatim as run.json (parameters, versions)
};

struct WrittenOutputs {
  std::vector<std::string> files;  ///< the paths written
  eval::TableOne table;                  ///< as written, for a command's summary
  eval::EligibilitySummary eligibility;
};

/// Creates `directory` if needed and writes every file atomically; the
/// records are written sorted.
WrittenOutputs writeExperimentOutputs(const std::string& directory, std::vector<eval::GraspRecord> records,
                                                const ExperimentOutputs& outputs);

}  // namespace icrkit::report
