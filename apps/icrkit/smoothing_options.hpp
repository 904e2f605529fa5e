#pragma once
// `--window-normal-angle RAD` as every command that smooths spells it
// (smooth, reconstruct, sensitivity): one-sided smoothing windows
// (ndt::SmoothingParameters::max_normal_angle).

#include <CLI/CLI.hpp>

namespace icrkit::app {

/// Adds the option, storing radians into `angle` (default pi: off).
CLI::Option* addWindowNormalAngleOption(CLI::App& command, double& angle);

/// `angle` when it is a usable window angle; InputError naming the flag otherwise.
double checkedWindowNormalAngle(double angle);

}  // namespace icrkit::app
