#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>

#include <cmath>
#include <string>

namespace icrkit::app {

CLI::Option* addWindowNormalAngleOption(CLI::App& command, double& angle) {
  return command
      .add_option("--window-normal-angle", angle,
                  "One-sided smoothing windows: a window keeps only points whose input normal is within this "
                  "angle (radians) of its centre's, so both sides of a wall thinner than the window stay apart "
                  "(1.5708: opposite-facing points left out); 3.1416 or more: every point (the paper's window)")
      ->capture_default_str();
}

double checkedWindowNormalAngle(double angle) {
  if (!(angle > 0) || !std::isfinite(angle))
    throw InputError("--window-normal-angle", "", "expected an angle > 0 radians, got " + std::to_string(angle));
  return angle;
}

}  // namespace icrkit::app
