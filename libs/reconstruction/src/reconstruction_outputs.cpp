#include <icrkit/reconstruction/reconstruction_outputs.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/ndt/preselection_record.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting_record.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>
#include <icrkit/reconstruction/registration/trajectory_error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kDeg = 180.0 / M_PI;

Json poseErrorJson(const PoseErrorSeries& s) {
  return {{"median_sensor_translation_mm", s.median_sensor_translation_m * 1e3},
          {"max_sensor_translation_mm", s.max_sensor_translation_m * 1e3},
          {"median_object_translation_mm", s.median_object_translation_m * 1e3},
          {"max_object_translation_mm", s.max_object_translation_m * 1e3},
          {"median_rotation_deg", s.median_rotation_rad * kDeg},
          {"max_rotation_deg", s.max_rotation_rad * kDeg}};
}

// The ball pivoting record (ball_pivoting_record.hpp) with the fields
// reconstruction.json has always carried for each mesh.
Json meshingJson(const BallPivotingReport& r) {
  const Json full = Json::parse(ballPivotingRecordJson(r));
  Json kept;
  for (const char* key : {"triangles", "used_points", "unused_points", "boundary_loops", "components",
                          "non_manifold_edges", "radii_m", "layer_thickness_m", "thinning_cell_m", "thinned_points",
                          "reinserted_points", "closed_holes", "folded_holes", "removed_faces"})
    kept[key] = full.at(key);
  return kept;
}

Json scanJson(const ReconstructionResult& result, std::size_t i) {
  const ScanFilterRecord& f = result.filters[i];
  Json scan{{"index", f.index},
            {"valid_pixels", f.valid_pixels},
            {"removed",
             {{"confidence", f.removed_confidence},
              {"jump_edges", f.removed_jump_edges},
              {"foreground_edges", f.removed_foreground_edges},
              {"range", f.removed_range},
              {"crop", f.removed_crop},
              {"support_plane", f.removed_plane}}},
            {"support_plane_found", f.plane_found},
            {"object_points", f.object_points},
            {"fused_points", i < result.fusion.kept_per_scan.size() ? result.fusion.kept_per_scan[i] : 0}};
  if (i < result.board_poses.size()) {
    const LatticePose& b = result.board_poses[i];
    scan["board"] = {{"found", b.found},
                     {"used", b.found && !result.board_pose_rejected[i]},
                     {"corners", b.corners},
                     {"rms_px", b.rms_px}};
  }
  if (i < result.registration.scans.size()) {
    const ScanRegistrationRecord& r = result.registration.scans[i];
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
  return scan;
}

// Median of the accepted pairs' ICP residuals (0 when none has one).
double medianIcpRmsMm(const SequenceRegistrationResult& registration) {
  std::vector<double> rms;
  for (const auto& p : registration.pairs)
    if (p.accepted && p.icp_rms_m > 0) rms.push_back(p.icp_rms_m * 1e3);
  if (rms.empty()) return 0.0;
  std::nth_element(rms.begin(), rms.begin() + static_cast<std::ptrdiff_t>(rms.size() / 2), rms.end());
  return rms[rms.size() / 2];
}

Json registrationJson(const ReconstructionResult& result, const ReconstructionParameters& params) {
  const SequenceRegistrationResult& r = result.registration;
  std::size_t registered = 0, pairs_accepted = 0;
  for (const auto& scan : r.scans) registered += scan.registered;
  for (const auto& pair : r.pairs) pairs_accepted += pair.accepted;
  const auto& loop = r.loop_closure;
  return {{"enabled", params.register_scans},
          {"registered_scans", registered},
          {"pairs", r.pairs.size()},
          {"pairs_accepted", pairs_accepted},
          {"loop_closure",
           {{"attempted", loop.attempted},
            {"accepted", loop.accepted},
            {"rejection", loop.rejection},
            {"discrepancy_mm", loop.discrepancy_translation_m * 1e3},
            {"discrepancy_deg", loop.discrepancy_rotation_rad * kDeg}}},
          {"pose_graph",
           {{"iterations", r.graph.iterations},
            {"initial_chi2", r.graph.initial_chi2},
            {"final_chi2", r.graph.final_chi2},
            {"converged", r.graph.converged}}},
          {"model_points", r.model_points},
          {"ndt_resolutions_m", r.resolutions},
          {"pair_variance_factor", r.pair_variance_factor},
          {"scan_to_model", params.registration.scan_to_model},
          {"as_scans_arrive", params.registration.incremental},
          {"multiway_rounds", r.refinement_rounds},
          {"unsettled_pairs_registered", r.unsettled_pairs_registered},
          {"unsettled_pairs_accepted", r.unsettled_pairs_accepted},
          {"pairs_retried_coarse", r.pairs_retried_coarse},
          {"pairs_retried_accepted", r.pairs_retried_accepted},
          {"model_alignment",
           {{"resolutions_m", r.model_alignment_resolutions},
            {"object_spread_mm", r.model_spread_m * 1e3},
            {"views_kept", r.model_alignment_accepted},
            {"reseat_tried", r.reseat_tried},
            {"reseat_moved", r.reseat_moved},
            {"reseat_searched", r.reseat_searched},
            {"median_move_mm", r.model_alignment_median_move_m * 1e3},
            {"max_move_mm", r.model_alignment_max_move_m * 1e3}}},
          {"joint_refinement",
           {{"enabled", params.register_scans && params.registration.joint_refinement},
            {"applied", r.joint_applied},
            {"rejection", r.joint_rejection},
            {"iterations", r.joint_iterations},
            {"linked_view_pairs", r.joint_linked_view_pairs},
            {"graph_view_pairs", r.joint_graph_view_pairs},
            {"rms_mm", r.joint_rms_m * 1e3}}},
          {"icp_median_rms_mm", medianIcpRmsMm(r)},
          {"stage_time_ms",
           {{"prepare", r.stage_times.prepare_ms},
            {"model_alignment", r.stage_times.model_alignment_ms},
            {"pairs", r.stage_times.pairs_ms},
            {"graph", r.stage_times.graph_ms},
            {"joint_refinement", r.stage_times.joint_ms}}},
          {"robot_precision",
           {{"measured_odometry_sigma_mm", r.measured_odometry_sigma_translation_m * 1e3},
            {"measured_odometry_sigma_deg", r.measured_odometry_sigma_rotation_rad * kDeg},
            {"odometry_sigma_mm", r.odometry_sigma_translation_m * 1e3},
            {"odometry_sigma_deg", r.odometry_sigma_rotation_rad * kDeg},
            {"prior_sigma_mm", r.prior_sigma_translation_m * 1e3},
            {"prior_sigma_deg", r.prior_sigma_rotation_rad * kDeg}}},
          {"first_scan_spacing_m", r.first_scan_spacing_m}};
}

Json smoothingJson(const ReconstructionResult& result, const ReconstructionParameters& params) {
  const ndt::SmoothingReport& s = result.smoothing;
  return {{"radius_m", s.radius_m},
          {"passes", s.passes},
          {"window_normal_angle_rad", params.smoothing.max_normal_angle},
          {"preselection", Json::parse(ndt::preselectionRecordJson(s.preselection))},
          {"excluded", s.preselection.excluded},
          {"cardinality_threshold", s.preselection.cardinality_threshold},
          {"flatness_threshold", s.preselection.flatness_threshold},
          {"mesh_kept_points_only", params.mesh_kept_points_only},
          {"dropped_excluded", result.dropped_excluded},
          {"mean_displacement_mm", s.mean_displacement_m * 1e3}};
}

// The registered and the reported poses against the ground truth, each after
// its best rigid alignment, measured at the crop box's centre (the object).
void addRegistrationError(Json& record, const ReconstructionResult& result, const GroundTruthPoses& truth) {
  const std::size_t n = result.poses.size();
  std::vector<Eigen::Isometry3d> true_poses;
  for (std::size_t i = 0; i < n; ++i) true_poses.push_back(truth.poses[i].pose);
  const Eigen::Vector3d centre = result.crop_box.center();
  const TrajectoryError registered = trajectoryError(result.poses, true_poses, centre);
  const TrajectoryError reported = trajectoryError(result.reported_poses, true_poses, centre);
  for (std::size_t i = 0; i < n; ++i)
    record["per_scan"][i]["registration_error"] = {
        {"object_translation_mm", registered.aligned.object_translation_m[i] * 1e3},
        {"sensor_translation_mm", registered.aligned.sensor_translation_m[i] * 1e3},
        {"rotation_deg", registered.aligned.rotation_rad[i] * kDeg},
        {"reported_object_translation_mm", reported.aligned.object_translation_m[i] * 1e3},
        {"reported_rotation_deg", reported.aligned.rotation_rad[i] * kDeg}};
  record["registration_error"] = {
      {"ground_truth", truth.file},
      {"ground_truth_poses_orthonormalised", truth.orthonormalised},
      {"object_point_m", {centre.x(), centre.y(), centre.z()}},
      {"registered", {{"raw", poseErrorJson(registered.raw)}, {"aligned", poseErrorJson(registered.aligned)}}},
      {"reported", {{"raw", poseErrorJson(reported.raw)}, {"aligned", poseErrorJson(reported.aligned)}}}};
}

Json nullOr(const std::string& text) {
  return text.empty() ? Json(nullptr) : Json(text);
}

void createDirectories(const fs::path& dir) {
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error))
    throw InputError(dir.string(), "", "exists and is not a directory");
  fs::create_directories(dir, error);
  if (error) throw InputError(dir.string(), "", "cannot create the directory: " + error.message());
}

}  // namespace

GroundTruthPoses readGroundTruthPoses(const std::string& input, const std::string& file,
                                      const ReconstructionParameters& params) {
  GroundTruthPoses truth;
  truth.file = file;
  std::vector<std::uint8_t> normalised;
  if (isDepthImageFolder(input)) {
    TumFolderOptions probe_options;
    probe_options.camera = params.depth_camera;
    probe_options.unproject = false;
    const TumFolderReader probe(input, probe_options);
    std::vector<double> times;
    for (const auto& frame : probe.frames()) times.push_back(frame.timestamp);
    // The folder's ground truth is in its own (optical) axes, like its poses.
    const MatchedPoses matched = matchOpticalPoses(file, times, params.max_time_difference);
    for (std::size_t i = 0; i < times.size(); ++i) truth.poses.push_back({times[i], matched.sensor_poses[i]});
    normalised = matched.normalised;
  } else if (isBag(input)) {
    // A bag's ground truth is in optical axes too (ROS's camera frames),
    // matched to its images by stamp like its pose topic.
    ScanReaderOptions probe_options = scanReaderOptions(params);
    probe_options.unproject = false;
    const ScanReader probe(input, probe_options);
    const std::vector<double> stamps = probe.bag()->imageStamps();
    const MatchedPoses matched = matchOpticalPoses(file, stamps, probe.bag()->maxTimeDifference());
    for (std::size_t i = 0; i < stamps.size(); ++i) truth.poses.push_back({stamps[i], matched.sensor_poses[i]});
    normalised = matched.normalised;
  } else {
    truth.poses = readTumTrajectory(file, &normalised);
  }
  truth.orthonormalised = static_cast<std::size_t>(std::count(normalised.begin(), normalised.end(), 1));
  return truth;
}

std::string reconstructionRecordJson(const ReconstructionResult& result, const ReconstructionParameters& params,
                                     const ReconstructionRecordInput& input) {
  const std::size_t n = result.poses.size();
  if (input.ground_truth && input.ground_truth->poses.size() < n) {
    const std::size_t have = input.ground_truth->poses.size();
    throw InputError(
        input.ground_truth->file, "scan " + std::to_string(have),
        "no ground-truth pose: the file has " + std::to_string(have) + " poses for " + std::to_string(n) + " scans");
  }
  Json scans = Json::array();
  for (std::size_t i = 0; i < n; ++i) scans.push_back(scanJson(result, i));
  // What the scan filters removed, over all scans; "jump_edges" are the
  // mixed (flying) pixels between a foreground edge and the background.
  Json removed = {{"confidence", 0}, {"jump_edges", 0}, {"foreground_edges", 0}, {"range", 0}, {"crop", 0}, {"support_plane", 0}};
  for (const ScanFilterRecord& f : result.filters) {
    removed["confidence"] = removed["confidence"].get<std::size_t>() + f.removed_confidence;
    removed["jump_edges"] = removed["jump_edges"].get<std::size_t>() + f.removed_jump_edges;
    removed["foreground_edges"] = removed["foreground_edges"].get<std::size_t>() + f.removed_foreground_edges;
    removed["range"] = removed["range"].get<std::size_t>() + f.removed_range;
    removed["crop"] = removed["crop"].get<std::size_t>() + f.removed_crop;
    removed["support_plane"] = removed["support_plane"].get<std::size_t>() + f.removed_plane;
  }
  const auto& box = result.crop_box;
  Json record{
      {"input", input.input},
      {"input_format", !input.input_format.empty()     ? input.input_format
                       : isBag(input.input)              ? "ros2_bag"
                       : isDepthImageFolder(input.input) ? "tum_folder"
                                                         : "rawlog"},
      {"output", input.output},
      {"scans", n},
      {"poses", nullOr(params.pose_file)},
      {"pose_matching", result.pose_matching},
      {"poses_orthonormalised", result.poses_orthonormalised},
      {"depth_camera", result.depth_camera ? Json::parse(depthCameraRecordJson(*result.depth_camera)) : Json(nullptr)},
      {"crop_box_m", {box.min().x(), box.min().y(), box.min().z(), box.max().x(), box.max().y(), box.max().z()}},
      {"crop_box_automatic", result.crop_box_automatic},
      {"up", {result.up.x(), result.up.y(), result.up.z()}},
      {"up_automatic", result.up_automatic},
      {"scan_spacing_m", result.scan_spacing_m},
      {"range_correction", nullOr(input.range_correction_file)},
      {"board", params.board
                    ? Json{{"square_m", params.board->square_size},
                           {"origin_m", {params.board->origin.x(), params.board->origin.y(), params.board->origin.z()}},
                           {"poses_from_board", result.poses_from_board}}
                    : Json(nullptr)},
      {"removed", removed},
      {"registration", registrationJson(result, params)},
      {"fusion",
       {{"points_in", result.fusion.points_in},
        {"kept", result.fusion.kept},
        {"dropped_free", result.fusion.dropped_free},
        {"dropped_outside", result.fusion.dropped_outside},
        {"voxel_m", params.fusion.resolution}}},
      {"cloud_points", result.cloud.positions.size()},
      {"per_scan", scans}};
  if (params.make_meshes) {
    if (params.make_raw_mesh) {
      record["raw_mesh"] = meshingJson(result.raw_meshing);
      record["mesh_radii_m"] = record["raw_mesh"]["radii_m"];
    }
    record["filtered_mesh"] = meshingJson(result.filtered_meshing);
    record["smoothing"] = smoothingJson(result, params);
  }
  if (input.ground_truth) addRegistrationError(record, result, *input.ground_truth);
  const ReconstructionTimes& t = result.times;
  record["time_ms"] = {{"read", t.read_ms},
                       {"filters", t.filter_ms},
                       {"registration", t.registration_ms},
                       {"fusion", t.fusion_ms},
                       {"normals", t.normals_ms},
                       {"raw_mesh", t.raw_mesh_ms},
                       {"smoothing", t.smoothing_ms},
                       {"filtered_mesh", t.filtered_mesh_ms},
                       {"pipeline", t.total_ms}};
  return record.dump();
}

void writeReconstructionFiles(const std::string& directory, const ReconstructionResult& result, bool meshes,
                              const std::string& registration_input_directory) {
  const fs::path dir(directory);
  createDirectories(dir);
  io::writePointCloud((dir / "cloud.ply").string(), result.cloud);
  if (meshes) {
    // A result made without the raw baseline (make_raw_mesh) has no raw
    // vertices; a made one has every fused point.
    if (!result.raw_mesh.vertices.positions.empty()) io::writeTriangleMesh((dir / "raw.ply").string(), result.raw_mesh);
    io::writeTriangleMesh((dir / "filtered.ply").string(), result.filtered_mesh);
  }
  std::vector<StampedPose> poses;
  for (std::size_t i = 0; i < result.poses.size(); ++i) poses.push_back({result.timestamps[i], result.poses[i]});
  writeTumTrajectory((dir / "poses.txt").string(), poses);
  if (registration_input_directory.empty()) return;
  if (result.registration_input.empty() && !result.poses.empty())
    throw InputError("registration input", "",
                     "the result holds no registration input (ReconstructionParameters::keep_registration_input)");
  const fs::path views(registration_input_directory);
  createDirectories(views);
  std::vector<StampedPose> starts;
  for (std::size_t i = 0; i < result.registration_input.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "view_%03zu.ply", i);
    io::writePointCloud((views / name).string(), result.registration_input[i]);
    starts.push_back({result.timestamps[i], result.reported_poses[i]});
  }
  writeTumTrajectory((views / "start.txt").string(), starts);
}

}  // namespace icrkit::reconstruction
