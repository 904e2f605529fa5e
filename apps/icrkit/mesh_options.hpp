#pragma once
// The flags of `icrkit mesh` and the ball pivoting and normal estimation
// parameters they ask for.

#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace icrkit::app {

struct MeshOptions {
  std::string input;
  std::string output;
  std::string radii;
  bool estimate_normals = false;
  std::string normal_radius = "3x";
  std::string viewpoint;
  double thinning = reconstruction::BallPivotingParameters{}.thinning_factor;
  bool no_reinsert = false;
  bool keep_folded_holes = false;
  std::size_t fill_holes = reconstruction::BallPivotingParameters{}.close_holes_up_to;
  std::size_t min_component_faces = 0;
};

/// Adds every flag of the command (the input and -o included) to `command`.
void addMeshOptions(CLI::App& command, MeshOptions& options);

/// --radii (metres or multiples of the spacing; given radii are all there
/// is), --thinning, --no-reinsert, --keep-folded-holes, --fill-holes,
/// --min-component-faces; checked (BallPivotingParameters::validate).
reconstruction::BallPivotingParameters ballPivotingParameters(const MeshOptions& options);

/// --normal-radius and --viewpoint.
ndt::NormalEstimationParameters normalEstimationParameters(const MeshOptions& options);

}  // namespace icrkit::app
