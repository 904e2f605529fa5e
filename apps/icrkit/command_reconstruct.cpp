// `icrkit reconstruct RAWLOG|FOLDER -o DIR`: the whole of Section II-A
// (reconstruction::reconstructRawlog) on a rawlog or a TUM RGB-D folder, and
// its files: DIR/cloud.ply (fused cloud), DIR/raw.ply and DIR/filtered.ply
// (meshes), DIR/poses.txt (TUM, MRPT's sensor axes, like a rawlog's
// sensorPose) and DIR/reconstruction.json.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "depth_folder_options.hpp"
#include "preselection_options.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/registration/trajectory_error.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct ReconstructOptions {
  std::string input;
  std::string output;
  std::string poses;
  std::string gt_poses;
  std::string images;
  std::string range_correction;
  std::string crop;
  double crop_size = 0.15;
  bool no_plane = false;
  bool no_registration = false;
  bool scan_to_model = false;
  std::string write_registration_input;
  bool no_jump_edges = false;
  bool no_meshes = false;
  int min_confidence = 0;
  int min_amplitude = 0;
  double max_range = 0.0;
  double voxel = 0.004;
  std::string smoothing_radius = "4x";
  int passes = 1;
  double window_normal_angle = M_PI;
  std::string preselection = "default";
  bool mesh_kept_points_only = false;
  double mesh_thinning = reconstruction::ReconstructionParameters{}.meshing.thinning_factor;
  double board_square = 0.0;
  std::string board_origin;
  DepthFolderFlags folder;
  double rotation_tolerance = kReadRotationTolerance;
  const CLI::App* command = nullptr;  // which options were given
};

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

nlohmann::json poseErrorJson(const reconstruction::PoseErrorSeries& s) {
  constexpr double kDeg = 180.0 / M_PI;
  return {{"median_sensor_translation_mm", s.median_sensor_translation_m * 1e3},
          {"max_sensor_translation_mm", s.max_sensor_translation_m * 1e3},
          {"median_object_translation_mm", s.median_object_translation_m * 1e3},
          {"max_object_translation_mm", s.max_object_translation_m * 1e3},
          {"median_rotation_deg", s.median_rotation_rad * kDeg},
          {"max_rotation_deg", s.max_rotation_rad * kDeg}};
}

nlohmann::json meshingJson(const reconstruction::BallPivotingReport& r) {
  return {{"triangles", r.triangles},       {"used_points", r.used_points},
          {"unused_points", r.unused_points}, {"boundary_loops", r.boundary_loops},
          {"components", r.components},     {"non_manifold_edges", r.non_manifold_edges},
          {"radii_m", [&r] {
             std::vector<double> radii;
             for (const auto& pass : r.passes) radii.push_back(pass.radius);
             return radii;
           }()},
          {"layer_thickness_m", r.layer_thickness}, {"thinning_cell_m", r.thinning_cell},
          {"thinned_points", r.thinned_points},     {"reinserted_points", r.reinserted_points},
          {"closed_holes", r.closed_holes},         {"folded_holes", r.folded_holes},
          {"removed_faces", r.removed_faces}};
}

nlohmann::json reconstruct(const ReconstructOptions& options, CommandContext& context) {
  reconstruction::ReconstructionParameters params;
  params.pose_file = options.poses;
  params.images_folder = options.images;
  const bool folder = reconstruction::isDepthImageFolder(options.input);
  if (folder) {
    if (!options.images.empty())
      throw InputError("--images", "", "applies to a rawlog input (its externally stored images), not a folder");
    params.depth_camera = depthCameraOptions(options.folder);
    params.max_time_difference = options.folder.max_time_difference;
  } else {
    refuseDepthFolderOptions(*options.command, options.folder);
  }
  if (!(options.rotation_tolerance >= 0) || !std::isfinite(options.rotation_tolerance))
    throw InputError("--rotation-tolerance", "", "expected max |R^T R - I| >= 0");
  params.rotation_tolerance = options.rotation_tolerance;
  if (!options.range_correction.empty())
    params.range_correction = reconstruction::readRangeErrorModel(options.range_correction);
  if (!options.crop.empty()) params.crop_box = parseBox("--crop", options.crop);
  if (!(options.crop_size > 0) || !std::isfinite(options.crop_size))
    throw InputError("--crop-size", "", "expected a positive half-size in metres");
  params.auto_crop_half_size = options.crop_size;
  params.remove_support_plane = !options.no_plane;
  params.register_scans = !options.no_registration;
  params.registration.scan_to_model = options.scan_to_model;
  params.keep_registration_input = !options.write_registration_input.empty();
  if (params.keep_registration_input && options.no_registration)
    throw InputError("--write-registration-input", "", "needs registration (drop --no-registration)");
  if (!options.board_origin.empty() && options.board_square == 0.0)
    throw InputError("--board-origin", "", "needs --board-square (the checkerboard's square size)");
  if (options.board_square != 0.0) {
    if (!(options.board_square > 0) || !std::isfinite(options.board_square))
      throw InputError("--board-square", "", "expected the checkerboard's square size in metres (> 0)");
    if (options.no_registration)
      throw InputError("--board-square", "", "the board poses enter the registration; drop --no-registration");
    reconstruction::BoardLattice board;
    board.square_size = options.board_square;
    if (!options.board_origin.empty()) board.origin = parsePoint("--board-origin", options.board_origin);
    params.board = board;
  }
  params.jump_edge_filter = !options.no_jump_edges;
  params.make_meshes = !options.no_meshes;
  if (options.min_confidence < 0 || options.min_confidence > 255)
    throw InputError("--min-confidence", "", "expected 0..255");
  if (options.min_amplitude < 0 || options.min_amplitude > 255) throw InputError("--min-amplitude", "", "expected 0..255");
  params.confidence.min_confidence = options.min_confidence;
  params.confidence.min_amplitude = options.min_amplitude;
  if (!(options.max_range >= 0) || !std::isfinite(options.max_range))
    throw InputError("--max-range", "", "expected 0 (none) or metres");
  params.range.max_range = options.max_range;
  if (!(options.voxel > 0) || !std::isfinite(options.voxel)) throw InputError("--voxel", "", "expected metres > 0");
  params.fusion.resolution = options.voxel;
  const Length radius = parseLength("--smoothing-radius", options.smoothing_radius);
  params.smoothing.radius = radius.relative ? 0.0 : radius.value;
  if (radius.relative) params.smoothing.radius_factor = radius.value;
  if (options.passes < 1) throw InputError("--passes", "", "expected at least 1");
  params.smoothing.passes = options.passes;
  params.smoothing.max_normal_angle = checkedWindowNormalAngle(options.window_normal_angle);
  params.smoothing.preselection.rule = ndt::parsePreselectionRule(options.preselection);
  params.mesh_kept_points_only = options.mesh_kept_points_only;
  if (!(std::isfinite(options.mesh_thinning) && options.mesh_thinning >= 0))
    throw InputError("--mesh-thinning", "", "expected a factor >= 0 (0: no thinning)");
  params.meshing.thinning_factor = options.mesh_thinning;

  // The ground truth is read (and for a folder matched to its frames)
  // before the long run, so that a bad file fails at once.
  std::vector<StampedPose> truth;
  std::size_t truth_normalised = 0;
  if (!options.gt_poses.empty()) {
    std::vector<std::uint8_t> normalised;
    if (folder) {
      reconstruction::TumFolderOptions probe_options;
      probe_options.camera = params.depth_camera;
      probe_options.unproject = false;
      const reconstruction::TumFolderReader probe(options.input, probe_options);
      std::vector<double> times;
      for (const auto& frame : probe.frames()) times.push_back(frame.timestamp);
      // The folder's ground truth is in its own (optical) axes, like --poses.
      const reconstruction::MatchedPoses matched =
          reconstruction::matchOpticalPoses(options.gt_poses, times, params.max_time_difference);
      for (std::size_t i = 0; i < times.size(); ++i) truth.push_back({times[i], matched.sensor_poses[i]});
      normalised = matched.normalised;
    } else {
      truth = readTumTrajectory(options.gt_poses, &normalised);
    }
    truth_normalised = static_cast<std::size_t>(std::count(normalised.begin(), normalised.end(), 1));
  }
  const fs::path dir(options.output);
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error))
    throw InputError(options.output, "", "exists and is not a directory");

  const reconstruction::ReconstructionResult result =
      reconstruction::reconstructRawlog(options.input, params, context.progress());
  if (result.depth_camera) {
    const std::string note = depthScaleNote(*result.depth_camera);
    if (!note.empty()) context.note(note);
  }
  const std::size_t n = result.poses.size();
  if (!truth.empty() && truth.size() < n)
    throw InputError(options.gt_poses, "scan " + std::to_string(truth.size()),
                     "no ground-truth pose: the file has " + std::to_string(truth.size()) + " poses for " +
                         std::to_string(n) + " scans");

  // Everything is computed before the first file is written.
  const double write_start = context.elapsedMs();
  fs::create_directories(dir, error);
  if (error) throw InputError(options.output, "", "cannot create the directory: " + error.message());
  io::writePointCloud((dir / "cloud.ply").string(), result.cloud);
  if (params.make_meshes) {
    io::writeTriangleMesh((dir / "raw.ply").string(), result.raw_mesh);
    io::writeTriangleMesh((dir / "filtered.ply").string(), result.filtered_mesh);
  }
  std::vector<StampedPose> poses;
  for (std::size_t i = 0; i < n; ++i) poses.push_back({result.timestamps[i], result.poses[i]});
  writeTumTrajectory((dir / "poses.txt").string(), poses);
  if (!options.write_registration_input.empty()) {
    const fs::path views(options.write_registration_input);
    fs::create_directories(views, error);
    if (error) throw InputError(options.write_registration_input, "", "cannot create the directory: " + error.message());
    std::vector<StampedPose> starts;
    for (std::size_t i = 0; i < result.registration_input.size(); ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "view_%03zu.ply", i);
      io::writePointCloud((views / name).string(), result.registration_input[i]);
      starts.push_back({result.timestamps[i], result.reported_poses[i]});
    }
    writeTumTrajectory((views / "start.txt").string(), starts);
  }

  constexpr double kDeg = 180.0 / M_PI;
  nlohmann::json scans = nlohmann::json::array();
  const auto& records = result.registration.scans;
  for (std::size_t i = 0; i < n; ++i) {
    const reconstruction::ScanFilterRecord& f = result.filters[i];
    nlohmann::json scan{{"index", f.index},
                        {"valid_pixels", f.valid_pixels},
                        {"removed",
                         {{"confidence", f.removed_confidence},
                          {"jump_edges", f.removed_jump_edges},
                          {"range", f.removed_range},
                          {"crop", f.removed_crop},
                          {"support_plane", f.removed_plane}}},
                        {"support_plane_found", f.plane_found},
                        {"object_points", f.object_points},
                        {"fused_points", i < result.fusion.kept_per_scan.size() ? result.fusion.kept_per_scan[i] : 0}};
    if (i < result.board_poses.size()) {
      const reconstruction::LatticePose& b = result.board_poses[i];
      scan["board"] = {{"found", b.found},
                       {"used", b.found && !result.board_pose_rejected[i]},
                       {"corners", b.corners},
                       {"rms_px", b.rms_px}};
    }
    if (i < records.size()) {
      const reconstruction::ScanRegistrationRecord& r = records[i];
      scan["registration"] = {{"registered", r.registered},
                              {"rejection", r.rejection},
                              {"normalized_score", r.normalized_score},
                              {"iterations", r.iterations},
                              {"degenerate_directions", r.degenerate_directions},
                              {"weakest_direction_ratio", r.weakest_direction_ratio},
                              {"correction_mm", r.correction_translation_m * 1e3},
                              {"correction_deg", r.correction_rotation_rad * kDeg},
                              {"time_ms", r.time_ms}};
    }
    scans.push_back(scan);
  }
  std::size_t pairs_accepted = 0;
  for (const auto& p : result.registration.pairs) pairs_accepted += p.accepted;
  const auto& box = result.crop_box;
  const auto& loop = result.registration.loop_closure;
  nlohmann::json summary{
      {"input", options.input},
      {"input_format", folder ? "tum_folder" : "rawlog"},
      {"output", options.output},
      {"scans", n},
      {"poses", options.poses.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.poses)},
      {"pose_matching", result.pose_matching},
      {"poses_orthonormalised", result.poses_orthonormalised},
      {"depth_camera", result.depth_camera ? depthCameraJson(*result.depth_camera) : nlohmann::json(nullptr)},
      {"crop_box_m", {box.min().x(), box.min().y(), box.min().z(), box.max().x(), box.max().y(), box.max().z()}},
      {"crop_box_automatic", result.crop_box_automatic},
      {"scan_spacing_m", result.scan_spacing_m},
      {"range_correction", options.range_correction.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.range_correction)},
      {"board",
       params.board ? nlohmann::json{{"square_m", params.board->square_size},
                                     {"origin_m", {params.board->origin.x(), params.board->origin.y(), params.board->origin.z()}},
                                     {"poses_from_board", result.poses_from_board}}
                    : nlohmann::json(nullptr)},
      {"registration",
       {{"enabled", params.register_scans},
        {"registered_scans", [&] {
           std::size_t k = 0;
           for (const auto& r : records) k += r.registered;
           return k;
         }()},
        {"pairs", result.registration.pairs.size()},
        {"pairs_accepted", pairs_accepted},
        {"loop_closure",
         {{"attempted", loop.attempted},
          {"accepted", loop.accepted},
          {"rejection", loop.rejection},
          {"discrepancy_mm", loop.discrepancy_translation_m * 1e3},
          {"discrepancy_deg", loop.discrepancy_rotation_rad * kDeg}}},
        {"pose_graph",
         {{"iterations", result.registration.graph.iterations},
          {"initial_chi2", result.registration.graph.initial_chi2},
          {"final_chi2", result.registration.graph.final_chi2},
          {"converged", result.registration.graph.converged}}},
        {"model_points", result.registration.model_points},
        {"ndt_resolutions_m", result.registration.resolutions},
        {"pair_variance_factor", result.registration.pair_variance_factor},
        {"scan_to_model", params.registration.scan_to_model},
        {"multiway_rounds", result.registration.refinement_rounds},
        {"icp_median_rms_mm", [&] {
           std::vector<double> rms;
           for (const auto& p : result.registration.pairs)
             if (p.accepted && p.icp_rms_m > 0) rms.push_back(p.icp_rms_m * 1e3);
           if (rms.empty()) return 0.0;
           std::nth_element(rms.begin(), rms.begin() + static_cast<std::ptrdiff_t>(rms.size() / 2), rms.end());
           return rms[rms.size() / 2];
         }()},
        {"robot_precision",
         {{"measured_odometry_sigma_mm", result.registration.measured_odometry_sigma_translation_m * 1e3},
          {"measured_odometry_sigma_deg", result.registration.measured_odometry_sigma_rotation_rad * kDeg},
          {"odometry_sigma_mm", result.registration.odometry_sigma_translation_m * 1e3},
          {"odometry_sigma_deg", result.registration.odometry_sigma_rotation_rad * kDeg},
          {"prior_sigma_mm", result.registration.prior_sigma_translation_m * 1e3},
          {"prior_sigma_deg", result.registration.prior_sigma_rotation_rad * kDeg}}},
        {"first_scan_spacing_m", result.registration.first_scan_spacing_m}}},
      {"fusion",
       {{"points_in", result.fusion.points_in},
        {"kept", result.fusion.kept},
        {"dropped_free", result.fusion.dropped_free},
        {"dropped_outside", result.fusion.dropped_outside},
        {"voxel_m", params.fusion.resolution}}},
      {"cloud_points", result.cloud.positions.size()},
      {"per_scan", scans}};
  if (params.make_meshes) {
    summary["mesh_radii_m"] = [&] {
      std::vector<double> radii;
      for (const auto& pass : result.raw_meshing.passes) radii.push_back(pass.radius);
      return radii;
    }();
    summary["raw_mesh"] = meshingJson(result.raw_meshing);
    summary["filtered_mesh"] = meshingJson(result.filtered_meshing);
    summary["smoothing"] = {{"radius_m", result.smoothing.radius_m},
                            {"passes", result.smoothing.passes},
                            {"window_normal_angle_rad", params.smoothing.max_normal_angle},
                            {"preselection", preselectionJson(result.smoothing.preselection)},
                            {"excluded", result.smoothing.preselection.excluded},
                            {"cardinality_threshold", result.smoothing.preselection.cardinality_threshold},
                            {"flatness_threshold", result.smoothing.preselection.flatness_threshold},
                            {"mesh_kept_points_only", params.mesh_kept_points_only},
                            {"dropped_excluded", result.dropped_excluded},
                            {"mean_displacement_mm", result.smoothing.mean_displacement_m * 1e3}};
  }
  if (!truth.empty()) {
    std::vector<Eigen::Isometry3d> true_poses;
    for (std::size_t i = 0; i < n; ++i) true_poses.push_back(truth[i].pose);
    const Eigen::Vector3d centre = result.crop_box.center();
    const auto registered = reconstruction::trajectoryError(result.poses, true_poses, centre);
    const auto reported = reconstruction::trajectoryError(result.reported_poses, true_poses, centre);
    for (std::size_t i = 0; i < n; ++i)
      summary["per_scan"][i]["registration_error"] = {
          {"object_translation_mm", registered.aligned.object_translation_m[i] * 1e3},
          {"sensor_translation_mm", registered.aligned.sensor_translation_m[i] * 1e3},
          {"rotation_deg", registered.aligned.rotation_rad[i] * kDeg},
          {"reported_object_translation_mm", reported.aligned.object_translation_m[i] * 1e3},
          {"reported_rotation_deg", reported.aligned.rotation_rad[i] * kDeg}};
    summary["registration_error"] = {
        {"ground_truth", options.gt_poses},
        {"ground_truth_poses_orthonormalised", truth_normalised},
        {"object_point_m", {centre.x(), centre.y(), centre.z()}},
        {"registered", {{"raw", poseErrorJson(registered.raw)}, {"aligned", poseErrorJson(registered.aligned)}}},
        {"reported", {{"raw", poseErrorJson(reported.raw)}, {"aligned", poseErrorJson(reported.aligned)}}}};
  }
  const auto& t = result.times;
  summary["time_ms"] = {{"read", t.read_ms},         {"filters", t.filter_ms},
                        {"registration", t.registration_ms}, {"fusion", t.fusion_ms},
                        {"normals", t.normals_ms},   {"raw_mesh", t.raw_mesh_ms},
                        {"smoothing", t.smoothing_ms}, {"filtered_mesh", t.filtered_mesh_ms},
                        {"pipeline", t.total_ms},   {"write", context.elapsedMs() - write_start},
                        {"total", context.elapsedMs()}};
  writeSummaryFile((dir / "reconstruction.json").string(), summary);
  return summary;
}

}  // namespace

void addReconstructCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "reconstruct",
      "Object reconstruction from an MRPT rawlog of range scans (Section II-A of Krug et al.): per-scan filters "
      "(confidence, jump edges, range, crop box, support plane), scan-to-model 3D-NDT registration from the "
      "reported poses, pair-wise registrations and loop closure in a pose graph (CHOLMOD), OctoMap fusion, then "
      "ball pivoting of the fused cloud (raw mesh) and of its 3D-NDT smoothed, preselected version (filtered "
      "mesh). Writes DIR/cloud.ply, DIR/raw.ply, DIR/filtered.ply, DIR/poses.txt (TUM, MRPT's sensor axes like a "
      "rawlog's sensorPose, for a folder too) and DIR/reconstruction.json. The input may also be a TUM RGB-D "
      "folder (depth.txt, 16-bit depth PNGs; docs/reconstruction_input.md)");
  auto options = std::make_shared<ReconstructOptions>();
  options->command = command;
  command
      ->add_option("input", options->input,
                   "Rawlog of CObservation3DRangeScan (plain or gzip), or a TUM RGB-D folder (depth.txt, depth/*.png)")
      ->required();
  command->add_option("-o,--output", options->output, "Output directory (created; files replaced atomically)")
      ->required();
  command->add_option("--poses", options->poses,
                      "TUM file of the sensor poses. Rawlog: MRPT sensor axes (x forward, y left, z up), the i-th "
                      "pose replaces the i-th scan's sensorPose. TUM folder: OPTICAL axes (x right, y down, z "
                      "forward), camera to object, like the folder's groundtruth.txt; matched by order or time stamp");
  command->add_option("--gt-poses", options->gt_poses,
                      "TUM file of true sensor poses, in the same axes and matched as --poses: the summary then "
                      "reports the registration error");
  addDepthFolderOptions(*command, options->folder);
  command
      ->add_option("--rotation-tolerance", options->rotation_tolerance,
                   "Largest max |R^T R - I| of a rawlog's sensorPose rotation that is projected onto the nearest "
                   "rotation (counted as poses_orthonormalised); beyond it the scan is refused")
      ->capture_default_str();
  command->add_option("--images", options->images, "Folder of externally stored images (default: <rawlog>_Images)");
  command->add_option("--range-correction", options->range_correction,
                      "ToF range error model (JSON from `icrkit calibrate-range`) removed from every scan first");
  command->add_option("--crop", options->crop,
                      "Object region xmin,ymin,zmin,xmax,ymax,zmax (metres, object frame). Default: a cube of "
                      "--crop-size around the point the views' optical axes converge on");
  command->add_option("--crop-size", options->crop_size, "Half edge of the automatic crop cube (metres)")
      ->capture_default_str();
  command->add_flag("--no-plane-removal", options->no_plane, "Keep the support plane (table, plate)");
  command->add_flag("--no-registration", options->no_registration, "Fuse at the reported poses");
  command->add_flag("--scan-to-model", options->scan_to_model,
                    "Register each scan against the scans before it first (the paper's sequential pass; slower, "
                    "rarely better: docs/reconstruction.md)");
  command->add_option("--write-registration-input", options->write_registration_input,
                      "Also write each scan's object points (sensor frame) and starting pose to this folder "
                      "(view_NNN.ply, start.txt): the registration's exact input, for other tools");
  command->add_option("--board-square", options->board_square,
                      "Setup B: the object stands on a checkerboard with squares of this size (metres) whose lines "
                      "lie on the object frame's x and y axes; each scan's camera pose found on it (intensity image) "
                      "becomes a robust prior in the registration's pose graph (docs/calibration.md)");
  command->add_option("--board-origin", options->board_origin,
                      "A corner of the checkerboard, object frame (x,y,z metres; default 0,0,0)");
  command->add_flag("--no-jump-edges", options->no_jump_edges, "Keep jump-edge (flying) pixels");
  command->add_flag("--no-meshes", options->no_meshes, "Stop after the fused cloud");
  command->add_option("--min-confidence", options->min_confidence, "Drop pixels below this confidence (0-255; 0 = off)")
      ->capture_default_str();
  command->add_option("--min-amplitude", options->min_amplitude,
                      "Drop ToF pixels below this amplitude (0-255; 0 = off)")
      ->capture_default_str();
  command->add_option("--max-range", options->max_range, "Drop returns further than this (metres; 0 = off)")
      ->capture_default_str();
  command->add_option("--voxel", options->voxel, "OctoMap voxel edge of the fusion (metres)")->capture_default_str();
  command
      ->add_option("--smoothing-radius", options->smoothing_radius,
                   "3D-NDT smoothing window: metres or a multiple of a single scan's median point spacing")
      ->capture_default_str();
  command->add_option("--passes", options->passes, "3D-NDT smoothing passes")->capture_default_str();
  addWindowNormalAngleOption(*command, options->window_normal_angle);
  addPreselectionOption(*command, options->preselection, "for the filtered mesh");
  command->add_option("--mesh-thinning", options->mesh_thinning,
                      "Noise-layer thinning of the smoothed cloud before ball pivoting, cube edge in layer "
                      "thicknesses; the thinned points are put back into the faces afterwards (docs/meshing.md; "
                      "0: none)")
      ->capture_default_str();
  command->add_flag("--mesh-kept-points-only", options->mesh_kept_points_only,
                    "Drop the excluded points before meshing the smoothed cloud (the filtered mesh then has no "
                    "excluded vertex)");
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) { context.mapFields({{"SmoothingParameters::radius", "--smoothing-radius"}, {"SmoothingParameters::radius_factor", "--smoothing-radius"}, {"SmoothingParameters::passes", "--passes"}});
    context.emit(reconstruct(*options, context)); };
  });
}

}  // namespace icrkit::app
