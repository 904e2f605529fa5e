#pragma once
// The flags of `icrkit sensitivity`, the study's parameters they give, and
// how each noise level's meshes are made (the libraries `icrkit reconstruct`
// uses: raw = ball pivoting with estimated normals, filtered = smoothing, the
// preselection rule, ball pivoting).

#include "experiment_options.hpp"

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/eval/sensitivity_study.hpp>

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace icrkit::app {

struct SensitivityOptions {
  std::string cad, object, name, output;
  double spacing = 0.0;
  std::string noise = "0,0.25,0.5,1";
  std::string rules = "default,paper-mean,none";
  bool mesh_kept_points_only = false;
  double window_normal_angle = M_PI;
  ExperimentOptions experiment;
};

/// Adds every flag of the command (-o included) to `command`.
void addSensitivityOptions(CLI::App& command, SensitivityOptions& o);

/// --noise, --preselection, --spacing, --seed and the experiment's flags
/// (the library checks the values: SensitivityParameters::noise_levels, ...).
eval::SensitivityParameters sensitivityParameters(const SensitivityOptions& o);

/// The raw and filtered meshes of one noisy sample, with one copy of the
/// filtered mesh per rule (reconstruction::meshRawAndFilteredPerRule).
eval::SensitivityMeshes buildMeshes(const PointCloud& noisy, const std::vector<std::string>& rules,
                                    bool kept_points_only, double window_normal_angle);

}  // namespace icrkit::app
