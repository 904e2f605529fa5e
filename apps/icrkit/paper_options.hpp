#pragma once
// The flags of `icrkit paper` and what they ask for: the datasets, and how
// each one's meshes are made for the study (eval::runStudy): simulated and
// reconstructed into the run folder, or with --reuse read from an earlier
// run's.

#include "command_context.hpp"
#include "experiment_options.hpp"

#include <icrkit/eval/study.hpp>
#include <icrkit/sim/dataset.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace icrkit::app {

struct PaperOptions {
  std::string output;
  std::string datasets;  ///< empty: all nine
  int views = 0;         ///< 0: each dataset's own
  bool reuse = false;
  bool mesh_kept_points_only = false;
  std::string smoothing = "feature";  ///< of the filtered meshes: feature (one-sided windows) or paper
  ExperimentOptions experiment = [] {
    ExperimentOptions e;
    e.preselection = "default";
    return e;
  }();
};

/// Adds every flag of the command (-o included) to `command`.
void addPaperOptions(CLI::App& command, PaperOptions& o);

/// --datasets (all nine when empty) with --views applied.
std::vector<sim::DatasetSpec> chosenDatasets(const PaperOptions& o);

/// The meshes of one dataset: simulated and reconstructed into the run
/// folder (or, with --reuse, read from an earlier run's), preselected again
/// by the rule asked for when reused, aligned when asked; what was done
/// goes into `info` (preselection, alignment) and `times`.
eval::StudyMeshes datasetMeshes(const PaperOptions& o, const sim::DatasetSpec& spec, const std::string& prefix,
                                const ProgressCallback& progress, CommandContext& context, nlohmann::json& info,
                                nlohmann::json& times);

}  // namespace icrkit::app
