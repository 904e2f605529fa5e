#pragma once
/// \file
/// The regions behind one grasp record, recomputed on demand: grasps.jsonl
/// keeps only their sizes and scores (a study has ~30,000 regions), so
/// renders and reports regrow the few they show.

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/experiment_records.hpp>

#include <vector>

namespace icrkit::eval {

struct GraspRegions {
  /// One vertex list per finger (sorted), on each mesh; empty when the record
  /// was not evaluated (its grasps were not eligible on both meshes).
  std::vector<std::vector<int>> cad, raw, filtered;
};

/// Regrows C^C, C^R and C^F of an evaluated record exactly as the experiment
/// did (same frame, contact model, TWS radius and growth mode; the filtered
/// mesh's `excluded` flags when config.preselection). Throws InputError when
/// the record's contacts do not fit the meshes.
GraspRegions regrowRegions(const DatasetMeshes& meshes, const ExperimentConfig& config, const GraspRecord& record);

}  // namespace icrkit::eval
