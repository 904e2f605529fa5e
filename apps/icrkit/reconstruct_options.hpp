#pragma once
// The flags of `icrkit reconstruct` and their translation into
// reconstruction::ReconstructionParameters (the library checks the values
// and names the field; command_reconstruct.cpp maps the fields to these flags).

#include "depth_folder_options.hpp"

#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <CLI/CLI.hpp>

#include <cmath>
#include <functional>
#include <string>

namespace icrkit::app {

struct ReconstructOptions {
  std::string input;
  std::string output;
  std::string poses;
  std::string gt_poses;
  /// A reference surface (the object's CAD mesh): the raw and filtered
  /// meshes' accuracy against it, after a rigid fit (surface.json).
  std::string gt_mesh;
  std::string images;
  std::string range_correction;
  std::string crop;
  double crop_size = 0.15;
  bool no_plane = false;
  std::string up;
  bool no_registration = false;
  bool scan_to_model = false;
  bool incremental_registration = false;
  bool joint_refinement = false;
  bool no_joint_refinement = false;
  std::string write_registration_input;
  bool no_jump_edges = false;
  int edge_erosion = 0;
  bool no_meshes = false;
  int min_confidence = 0;
  int min_amplitude = 0;
  double max_range = 0.0;
  double voxel = 0.004;
  std::string smoothing_radius = "4x";
  int passes = 1;
  double window_normal_angle = reconstruction::kFeatureWindowNormalAngle;
  /// "feature" (one-sided windows, the default) or "paper" (Algorithm 1's
  /// window: every point of the radius); --window-normal-angle overrides.
  std::string smoothing = "feature";
  std::function<bool()> window_angle_given;  ///< set by addReconstructOptions
  std::string preselection = "default";
  bool mesh_kept_points_only = false;
  double mesh_thinning = reconstruction::ReconstructionParameters{}.meshing.thinning_factor;
  double board_square = 0.0;
  std::string board_origin;
  DepthFolderFlags folder;
  BagFlags bag;
  double rotation_tolerance = kReadRotationTolerance;
  const CLI::App* command = nullptr;  // which options were given
};

/// Adds every flag of the command (the input and -o included) to `command`.
void addReconstructOptions(CLI::App& command, ReconstructOptions& options);

/// The parameters the flags ask for. Refuses, naming the flags, the
/// combinations only the command line can get wrong (a folder-only flag
/// with a rawlog, --board-origin without --board-square, ...) and text that
/// does not parse (--crop, --board-origin, --smoothing-radius).
reconstruction::ReconstructionParameters reconstructionParameters(const ReconstructOptions& options);

}  // namespace icrkit::app
