#include "reconstruct_options.hpp"

#include "argument_parsing.hpp"
#include "preselection_options.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>

#include <vector>

namespace icrkit::app {
namespace {

Eigen::AlignedBox3d parseBox(const std::string& option, const std::string& text) {
  const std::vector<std::string> items = split(text, ',');
  double v[6];
  if (items.size() != 6)
    throw InputError(option, "", "expected xmin,ymin,zmin,xmax,ymax,zmax in metres, got '" + text + "'");
  for (int i = 0; i < 6; ++i)
    if (!parseNumber(items[static_cast<std::size_t>(i)], v[i]))
      throw InputError(option, "", "'" + items[static_cast<std::size_t>(i)] + "' is not a number");
  const Eigen::AlignedBox3d box(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
  if (!(v[0] < v[3] && v[1] < v[4] && v[2] < v[5]))
    throw InputError(option, "", "expected each minimum below its maximum, got '" + text + "'");
  return box;
}

Eigen::Vector3d parseDirection(const std::string& option, const std::string& text) {
  const std::vector<std::string> items = split(text, ',');
  if (items.size() != 3) throw InputError(option, "", "expected x,y,z (a direction), got '" + text + "'");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i)
    if (!parseNumber(items[static_cast<std::size_t>(i)], v[i]))
      throw InputError(option, "", "'" + items[static_cast<std::size_t>(i)] + "' is not a number");
  if (!v.allFinite() || !(v.norm() > 1e-9))
    throw InputError(option, "", "expected a non-zero, finite direction, got '" + text + "'");
  return v.normalized();
}

}  // namespace

void addReconstructOptions(CLI::App& command, ReconstructOptions& options) {
  options.command = &command;
  command
      .add_option("input", options.input,
                  "Rawlog of CObservation3DRangeScan (plain or gzip), a TUM RGB-D folder (depth.txt, depth/*.png) "
                  "or a ROS 2 bag (.mcap: depth images, CameraInfo, poses from a topic or tf)")
      ->required();
  command.add_option("-o,--output", options.output, "Output directory (created; files replaced atomically)")
      ->required();
  command.add_option("--poses", options.poses,
                     "TUM file of the sensor poses. Rawlog: MRPT sensor axes (x forward, y left, z up), the i-th "
                     "pose replaces the i-th scan's sensorPose. TUM folder: OPTICAL axes (x right, y down, z "
                     "forward), camera to object, like the folder's groundtruth.txt; matched by order or time stamp");
  command.add_option("--gt-poses", options.gt_poses,
                     "TUM file of true sensor poses, in the same axes and matched as --poses: the summary then "
                     "reports the registration error");
  command.add_option("--gt-mesh", options.gt_mesh,
                     "Reference surface of the object (its CAD mesh, metres): the raw and filtered meshes are fitted "
                     "to it (point-to-plane ICP) and measured per vertex, distance and normal error near its sharp "
                     "edges and elsewhere, in DIR/surface.json and the summary (docs/evaluation.md)");
  addDepthFolderOptions(command, options.folder);
  addBagOptions(command, options.bag);
  command
      .add_option("--rotation-tolerance", options.rotation_tolerance,
                  "Largest max |R^T R - I| of a rawlog's sensorPose rotation that is projected onto the nearest "
                  "rotation (counted as poses_orthonormalised); beyond it the scan is refused")
      ->capture_default_str();
  command.add_option("--images", options.images, "Folder of externally stored images (default: <rawlog>_Images)");
  command.add_option("--range-correction", options.range_correction,
                     "ToF range error model (JSON from `icrkit calibrate-range`) removed from every scan first");
  command.add_option("--crop", options.crop,
                     "Object region xmin,ymin,zmin,xmax,ymax,zmax (metres, object frame). Default: a cube of "
                     "--crop-size around the point the views' optical axes converge on");
  command.add_option("--crop-size", options.crop_size, "Half edge of the automatic crop cube (metres)")
      ->capture_default_str();
  command.add_flag("--no-plane-removal", options.no_plane, "Keep the support plane (table, plate)");
  command.add_option("--up", options.up,
                     "The object frame's up direction x,y,z: where the support plane is searched. Default: "
                     "estimated from the sensor poses (+z unless the upright views say another axis)");
  command.add_flag("--no-registration", options.no_registration, "Fuse at the reported poses");
  command.add_flag("--scan-to-model", options.scan_to_model,
                   "Register each scan against the scans before it first (the paper's sequential pass; slower, "
                   "rarely better: docs/reconstruction.md)");
  command.add_flag("--no-joint-refinement", options.no_joint_refinement,
                   "Keep the pose graph's poses: skip the last step, which refines all views at once against each "
                   "other's face-on points (docs/reconstruction.md, \"The joint refinement by default\")");
  command.add_flag("--joint-refinement", options.joint_refinement,
                   "The default (kept for scripts of earlier versions)");
  command.add_flag("--register-as-scans-arrive", options.incremental_registration,
                   "Register each scan with the earlier ones as it is read (what a stream does to be ready soon "
                   "after its last frame) instead of all views together at the end: docs/reconstruction.md, \"Streaming\"");
  command.add_option("--write-registration-input", options.write_registration_input,
                     "Also write each scan's object points (sensor frame) and starting pose to this folder "
                     "(view_NNN.ply, start.txt): the registration's exact input, for other tools");
  command.add_option("--board-square", options.board_square,
                     "Setup B: the object stands on a checkerboard with squares of this size (metres) whose lines "
                     "lie on the object frame's x and y axes; each scan's camera pose found on it (intensity image) "
                     "becomes a robust prior in the registration's pose graph (docs/calibration.md)");
  command.add_option("--board-origin", options.board_origin,
                     "A corner of the checkerboard, object frame (x,y,z metres; default 0,0,0)");
  command.add_flag("--no-jump-edges", options.no_jump_edges, "Keep jump-edge (flying) pixels");
  command
      .add_option("--edge-erosion", options.edge_erosion,
                  "Pixels taken off each foreground edge (a surface in front of the background or of no "
                  "return), where depth cameras spread or mix the edge; 0 keeps them")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  command.add_flag("--no-meshes", options.no_meshes, "Stop after the fused cloud");
  command.add_option("--min-confidence", options.min_confidence, "Drop pixels below this confidence (0-255; 0 = off)")
      ->capture_default_str();
  command.add_option("--min-amplitude", options.min_amplitude, "Drop ToF pixels below this amplitude (0-255; 0 = off)")
      ->capture_default_str();
  command.add_option("--max-range", options.max_range, "Drop returns further than this (metres; 0 = off)")
      ->capture_default_str();
  command.add_option("--voxel", options.voxel, "OctoMap voxel edge of the fusion (metres)")->capture_default_str();
  command
      .add_option("--smoothing-radius", options.smoothing_radius,
                  "3D-NDT smoothing window: metres or a multiple of a single scan's median point spacing")
      ->capture_default_str();
  command.add_option("--passes", options.passes, "3D-NDT smoothing passes")->capture_default_str();
  auto* window_angle = addWindowNormalAngleOption(command, options.window_normal_angle);
  command
      .add_option("--smoothing", options.smoothing,
                  "Smoothing of the filtered mesh: feature (one-sided windows of --window-normal-angle, 30 deg: "
                  "no blending across creases and thin walls) or paper (Algorithm 1's window, every point of the "
                  "radius, as Table I was published)")
      ->check(CLI::IsMember({"feature", "paper"}))
      ->capture_default_str();
  options.window_angle_given = [window_angle] { return window_angle->count() > 0; };
  addPreselectionOption(command, options.preselection, "for the filtered mesh");
  command
      .add_option("--mesh-thinning", options.mesh_thinning,
                  "Noise-layer thinning of the smoothed cloud before ball pivoting, cube edge in layer "
                  "thicknesses; the thinned points are put back into the faces afterwards (docs/meshing.md; "
                  "0: none)")
      ->capture_default_str();
  command.add_flag("--mesh-kept-points-only", options.mesh_kept_points_only,
                   "Drop the excluded points before meshing the smoothed cloud (the filtered mesh then has no "
                   "excluded vertex)");
}

reconstruction::ReconstructionParameters reconstructionParameters(const ReconstructOptions& options) {
  reconstruction::ReconstructionParameters params;
  params.pose_file = options.poses;
  params.images_folder = options.images;
  if (reconstruction::isBag(options.input)) {
    if (!options.images.empty())
      throw InputError("--images", "", "applies to a rawlog input (its externally stored images), not a ROS 2 bag");
    if (!options.poses.empty())
      throw InputError("--poses", "",
                       "a ROS 2 bag takes its poses from a PoseStamped topic (--pose-topic) or tf (--frames)");
    params.mcap = mcapReaderOptions(options.bag, options.folder);
    params.depth_camera.intrinsics = params.mcap.intrinsics;
    params.depth_camera.depth_scale = params.mcap.depth_scale;
    params.max_time_difference = options.folder.max_time_difference;
  } else if (reconstruction::isDepthImageFolder(options.input)) {
    if (!options.images.empty())
      throw InputError("--images", "", "applies to a rawlog input (its externally stored images), not a folder");
    refuseBagOptions(options.bag, "TUM folder");
    params.depth_camera = depthCameraOptions(options.folder);
    params.max_time_difference = options.folder.max_time_difference;
  } else {
    refuseBagOptions(options.bag, "rawlog");
    refuseDepthFolderOptions(*options.command, options.folder);
  }
  params.rotation_tolerance = options.rotation_tolerance;
  if (!options.range_correction.empty())
    params.range_correction = reconstruction::readRangeErrorModel(options.range_correction);
  if (!options.crop.empty()) params.crop_box = parseBox("--crop", options.crop);
  params.auto_crop_half_size = options.crop_size;
  params.remove_support_plane = !options.no_plane;
  if (!options.up.empty()) params.up = parseDirection("--up", options.up);
  params.register_scans = !options.no_registration;
  params.registration.scan_to_model = options.scan_to_model;
  params.registration.incremental = options.incremental_registration;
  if (options.joint_refinement && options.no_joint_refinement)
    throw InputError("--joint-refinement", "", "one of --joint-refinement and --no-joint-refinement");
  params.registration.joint_refinement = !options.no_joint_refinement;
  if (options.joint_refinement && options.no_registration)
    throw InputError("--joint-refinement", "", "needs registration (drop --no-registration)");
  params.keep_registration_input = !options.write_registration_input.empty();
  if (params.keep_registration_input && options.no_registration)
    throw InputError("--write-registration-input", "", "needs registration (drop --no-registration)");
  if (options.incremental_registration && options.no_registration)
    throw InputError("--register-as-scans-arrive", "", "needs registration (drop --no-registration)");
  if (!options.board_origin.empty() && options.board_square == 0.0)
    throw InputError("--board-origin", "", "needs --board-square (the checkerboard's square size)");
  if (options.board_square != 0.0) {
    if (options.no_registration && options.board_square > 0)
      throw InputError("--board-square", "", "the board poses enter the registration; drop --no-registration");
    reconstruction::BoardLattice board;
    board.square_size = options.board_square;
    if (!options.board_origin.empty()) board.origin = parsePoint("--board-origin", options.board_origin);
    params.board = board;
  }
  params.jump_edge_filter = !options.no_jump_edges;
  params.foreground_edges.pixels = options.edge_erosion;
  params.make_meshes = !options.no_meshes;
  params.confidence.min_confidence = options.min_confidence;
  params.confidence.min_amplitude = options.min_amplitude;
  params.range.max_range = options.max_range;
  params.fusion.resolution = options.voxel;
  params.smoothing.radius = parseLength("--smoothing-radius", options.smoothing_radius);
  params.smoothing.passes = options.passes;
  params.smoothing.max_normal_angle = checkedWindowNormalAngle(
      options.smoothing == "paper" && !(options.window_angle_given && options.window_angle_given()) ? M_PI
                                                                                                   : options.window_normal_angle);
  params.smoothing.preselection.rule = ndt::parsePreselectionRule(options.preselection, "--preselection");
  params.mesh_kept_points_only = options.mesh_kept_points_only;
  params.meshing.thinning_factor = options.mesh_thinning;
  return params;
}

}  // namespace icrkit::app
