// The whole pipeline on a simulated Kinect / setup B recording of the cup
// with the simulator's default robot pose errors: registration error
// against the ground truth, fused cloud against the CAD mesh, meshes and
// their attributes, checkerboard poses (setup B), and bad input.

#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_distance.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>
#include <icrkit/reconstruction/registration/trajectory_error.hpp>
#include <icrkit/sim/range_sensor.hpp>

#include <gtest/gtest.h>

#include <iostream>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace icrkit::reconstruction {
namespace {

using testing_support::scratchFolder;
using testing_support::simulatedRecording;

constexpr double kDeg = M_PI / 180.0;

// The sensor model's range noise for the fused points as they were
// measured: each point's own range (the SR4000's along the ray, the
// Kinect's depth along the optical axis) and incidence on the CAD surface
// (normal of the nearest CAD vertex), the object's reflectivity 0.6. Returns
// the median sigma over the points (metres): the typical noise; a mean would
// be ruled by the few points near grazing incidence, where the Kinect
// model's sigma grows without bound.
double modelledNoiseOfTheFusedPoints(const PointCloud& cloud, const std::vector<Eigen::Isometry3d>& poses,
                                     const Eigen::Isometry3d& alignment, TriangleMesh cad, sim::SensorType sensor) {
  const sim::SensorModel model = sim::sensorModel(sensor);
  computeVertexNormals(cad);
  const KdTree cad_vertices(cad.vertices.positions);
  const auto& view = cloud.attributes.get("view").values;
  std::vector<double> sigmas;
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    const Eigen::Isometry3d pose = alignment * poses[static_cast<std::size_t>(view[i])];
    const Eigen::Vector3d p = alignment * cloud.positions[i];
    const Eigen::Vector3d ray = p - pose.translation();
    const Eigen::Vector3d normal = cad.vertices.normals[cad_vertices.nearest(p, 1).front().index];
    const double incidence = std::acos(std::min(1.0, std::abs(normal.dot(ray.normalized()))));
    // MRPT's sensor axes: +x is the optical axis.
    const double range = model.range_is_depth ? ray.dot(pose.linear().col(0)) : ray.norm();
    sigmas.push_back(sim::rangeNoiseSigma(model, range, incidence));
  }
  std::nth_element(sigmas.begin(), sigmas.begin() + static_cast<std::ptrdiff_t>(sigmas.size() / 2), sigmas.end());
  return sigmas[sigmas.size() / 2];
}

void reconstructSimulatedCup(sim::SensorType sensor, double range) {
  const std::string dir = simulatedRecording(12, false, sensor);
  ReconstructionParameters params;
  std::size_t progress_calls = 0;
  const ReconstructionResult r =
      reconstructRawlog(dir + "/scans.rawlog", params, [&](const std::string&, std::size_t, std::size_t) { ++progress_calls; });
  ASSERT_EQ(r.poses.size(), 12u);
  EXPECT_GT(progress_calls, 24u);
  EXPECT_TRUE(r.crop_box_automatic);

  std::vector<Eigen::Isometry3d> truth;
  for (const StampedPose& p : readTumTrajectory(dir + "/ground_truth.txt")) truth.push_back(p.pose);
  const TrajectoryError registered = trajectoryError(r.poses, truth, r.crop_box.center());
  const TrajectoryError reported = trajectoryError(r.reported_poses, truth, r.crop_box.center());
  std::printf("registered: sensor median %.3f mm (max %.3f), rotation median %.3f deg (max %.3f); reported: %.3f mm, "
              "%.3f deg; %zu/%zu pairs accepted\n",
              registered.aligned.median_sensor_translation_m * 1e3, registered.aligned.max_sensor_translation_m * 1e3,
              registered.aligned.median_rotation_rad / kDeg, registered.aligned.max_rotation_rad / kDeg,
              reported.aligned.median_sensor_translation_m * 1e3, reported.aligned.median_rotation_rad / kDeg,
              std::size_t(std::count_if(r.registration.pairs.begin(), r.registration.pairs.end(),
                                        [](const PairRegistrationRecord& p) { return p.accepted; })),
              r.registration.pairs.size());
  // Registration is judged by the surface it makes (below, and issue 35's
  // decision); the poses only have to stay near the truth. With the robot's
  // precision measured by the model alignment the SR4000 cup's camera
  // positions are 1.5 mm off (1.0 before) while its fused cloud came closer
  // to the CAD mesh (1.00 instead of 1.05 mm; 0.91 at the true poses).
  EXPECT_LE(registered.aligned.median_sensor_translation_m, 2e-3);
  EXPECT_LE(registered.aligned.median_rotation_rad, 0.3 * kDeg);
  EXPECT_TRUE(r.registration.graph.converged);

  // The fused cloud against the CAD mesh, after the best-fit alignment of
  // the trajectory (the registration cannot see the robot's constant
  // hand-eye offset).
  const TriangleMesh cad = io::readTriangleMesh(dir + "/object.ply");
  auto meanDistanceToCad = [&](const PointCloud& cloud, const Eigen::Isometry3d& alignment) {
    TriangleMesh cloud_as_mesh;
    for (const Eigen::Vector3d& p : cloud.positions) cloud_as_mesh.vertices.positions.push_back(alignment * p);
    MeshDistanceParameters distance_params;
    distance_params.samples = 0;
    return meshDistance(cloud_as_mesh, cad, distance_params);
  };
  const MeshDistanceStatistics d = meanDistanceToCad(r.cloud, registered.alignment);
  // The same pipeline fused at the true poses: the error the sensor model
  // itself produces (its random noise at every incidence, plus what the
  // sigma below leaves out: lateral noise, the SR4000's wiggling).
  ReconstructionParameters true_poses;
  true_poses.pose_file = dir + "/ground_truth.txt";
  true_poses.register_scans = false;
  true_poses.make_meshes = false;
  const MeshDistanceStatistics floor =
      meanDistanceToCad(reconstructRawlog(dir + "/scans.rawlog", true_poses).cloud, Eigen::Isometry3d::Identity());
  const double sigma = sim::rangeNoiseSigma(sim::sensorModel(sensor), range, 0.0);
  const double sigma_measured = modelledNoiseOfTheFusedPoints(r.cloud, r.poses, registered.alignment, cad, sensor);
  std::printf("fused %zu points: mean distance to the CAD mesh %.3f mm (median %.3f, max %.2f); at the true poses "
              "%.3f mm; modelled range sigma at %.1f m, normal incidence: %.3f mm; median over the fused points at "
              "their own range and incidence: %.3f mm\n",
              r.cloud.positions.size(), d.mean * 1e3, d.median * 1e3, d.max * 1e3, floor.mean * 1e3, range,
              sigma * 1e3, sigma_measured * 1e3);
  EXPECT_LE(d.mean, 1.5 * floor.mean);
  EXPECT_LE(d.mean, 1.2 * floor.mean) << "the registration's surface (1.10x the true poses' on the SR4000 cup)";
  // The acceptance reading: within 1.5x the model's noise for these very
  // measurements (docs/reconstruction.md). The stricter best case, normal
  // incidence at the working range, holds for the Kinect only (below).
  EXPECT_LE(d.mean, 1.5 * sigma_measured);
  if (sensor == sim::SensorType::Kinect) {
    EXPECT_LE(d.mean, 1.5 * sigma);
  } else {
    // The SR4000's systematic range error, calibrated on another recording
    // (another object, exact poses) and removed: the fused cloud comes
    // closer to the CAD mesh, at the true poses and registered.
    const std::string reference = simulatedRecording(8, true, sensor, "paper_cup");
    const RangeErrorModel correction =
        calibrateRangeError(reference + "/scans.rawlog", {}, io::readTriangleMesh(reference + "/scene.ply")).model;
    ReconstructionParameters corrected = params;
    corrected.range_correction = correction;
    const ReconstructionResult rc = reconstructRawlog(dir + "/scans.rawlog", corrected);
    const TrajectoryError rc_error = trajectoryError(rc.poses, truth, rc.crop_box.center());
    const MeshDistanceStatistics dc = meanDistanceToCad(rc.cloud, rc_error.alignment);
    true_poses.range_correction = correction;
    const MeshDistanceStatistics floor_corrected =
        meanDistanceToCad(reconstructRawlog(dir + "/scans.rawlog", true_poses).cloud, Eigen::Isometry3d::Identity());
    std::printf("with the range correction: registration sensor median %.3f mm, rotation median %.3f deg; mean "
                "distance to the CAD mesh %.3f mm (at the true poses %.3f mm)\n",
                rc_error.aligned.median_sensor_translation_m * 1e3, rc_error.aligned.median_rotation_rad / kDeg,
                dc.mean * 1e3, floor_corrected.mean * 1e3);
    // 1.06 mm since the multiway ICP pairs (0.95 mm and below before): the
    // camera positions move a little, while the scans' points at the object
    // (what the fused cloud is made of) come closer to the truth than the
    // reported poses put them.
    EXPECT_LE(rc_error.aligned.median_sensor_translation_m, 2e-3);
    EXPECT_LE(rc_error.aligned.median_rotation_rad, 0.3 * kDeg);
    const TrajectoryError rc_reported = trajectoryError(rc.reported_poses, truth, rc.crop_box.center());
    EXPECT_LT(rc_error.aligned.median_object_translation_m, rc_reported.aligned.median_object_translation_m);
    EXPECT_LT(floor_corrected.mean, 0.75 * floor.mean);
    EXPECT_LT(dc.mean, d.mean);
    EXPECT_LE(dc.mean, 1.5 * modelledNoiseOfTheFusedPoints(rc.cloud, rc.poses, rc_error.alignment, cad, sensor));
    // Not yet within 1.5x of that floor (0.94 against 0.51 mm here): what
    // remains is the pose error, the robot's hand-eye rotation carried
    // through its odometry (docs/reconstruction.md).
  }

  // Attributes: the fusion's on the cloud and both meshes; preselection's on the filtered mesh.
  for (const char* name : {"view", "pixel", "viewpoint_x", "viewpoint_y", "viewpoint_z"}) {
    EXPECT_TRUE(r.cloud.attributes.has(name)) << name;
    EXPECT_TRUE(r.raw_mesh.vertices.attributes.has(name)) << name;
  }
  EXPECT_TRUE(r.cloud.hasNormals());
  EXPECT_EQ(r.raw_mesh.vertices.positions.size(), r.cloud.positions.size());
  EXPECT_GT(r.raw_mesh.faces.size(), r.cloud.positions.size() / 2);
  EXPECT_EQ(r.raw_meshing.thinned_points, 0u);  // the raw baseline keeps every point
  // Where the smoothed layer is thinned (a Kinect layer as thick as its
  // spacing), the thinned points go back into the faces: the mesh covers
  // most points, nearly two faces each.
  std::cout << "filtered mesh: " << r.filtered_meshing.used_points << "/" << r.cloud.positions.size() << " used, "
            << r.filtered_meshing.thinned_points << " thinned, " << r.filtered_meshing.reinserted_points
            << " put back, " << r.filtered_meshing.boundary_loops << " loops\n";
  EXPECT_GE(r.filtered_meshing.reinserted_points, 3 * r.filtered_meshing.thinned_points / 4);
  // 41 loops with three multiway rounds, 56 with two (stop 49): the
  // thinned Kinect layer's small holes move with sub-millimetre pose changes.
  EXPECT_LE(r.filtered_meshing.boundary_loops, 65u);
  EXPECT_EQ(r.filtered_meshing.non_manifold_edges, 0u);
  EXPECT_GT(r.filtered_meshing.triangles, 3 * r.filtered_meshing.used_points / 2);
  EXPECT_GE(r.filtered_meshing.used_points, 3 * r.cloud.positions.size() / 4);
  EXPECT_TRUE(r.filtered_mesh.vertices.attributes.has("excluded"));
  EXPECT_EQ(r.raw_meshing.non_manifold_edges, 0u);
  // The support plate is gone: nothing below the object's base (z = 0).
  std::size_t below = 0;
  for (const Eigen::Vector3d& p : r.cloud.positions) below += (registered.alignment * p).z() < -0.003;
  EXPECT_LT(below, r.cloud.positions.size() / 1000) << below << " points below the object";
}

TEST(ReconstructionPipeline, SimulatedKinectRecording) { reconstructSimulatedCup(sim::SensorType::Kinect, 0.7); }
TEST(ReconstructionPipeline, SimulatedSr4000Recording) { reconstructSimulatedCup(sim::SensorType::Sr4000, 0.6); }

TEST(ReconstructionPipeline, CheckerboardPosesAnchorTheRegistration) {
  // Setup B: the cup stands on the simulator's plate, 2 cm squares with
  // lines on the object frame's axes, 0.1 mm below the object's base.
  const std::string dir = simulatedRecording(12, false, sim::SensorType::Kinect);
  ReconstructionParameters params;
  params.make_meshes = false;
  BoardLattice board;
  board.origin = Eigen::Vector3d(0, 0, -1e-4);
  params.board = board;
  const ReconstructionResult r = reconstructRawlog(dir + "/scans.rawlog", params);
  ASSERT_EQ(r.board_poses.size(), 12u);
  EXPECT_GE(r.poses_from_board, 10u);
  std::vector<Eigen::Isometry3d> truth, seeds;
  for (const StampedPose& p : readTumTrajectory(dir + "/ground_truth.txt")) truth.push_back(p.pose);
  for (std::size_t i = 0; i < r.board_poses.size(); ++i)
    seeds.push_back(r.board_poses[i].found ? r.board_poses[i].sensor_pose : r.reported_poses[i]);
  const TrajectoryError seeded = trajectoryError(seeds, truth, r.crop_box.center());
  const TrajectoryError registered = trajectoryError(r.poses, truth, r.crop_box.center());
  const TrajectoryError reported = trajectoryError(r.reported_poses, truth, r.crop_box.center());
  ReconstructionParameters without_board = params;
  without_board.board.reset();
  const ReconstructionResult plain = reconstructRawlog(dir + "/scans.rawlog", without_board);
  EXPECT_TRUE(plain.board_poses.empty());
  const TrajectoryError robot_only = trajectoryError(plain.poses, truth, plain.crop_box.center());
  std::printf("board poses for %zu/12 scans: seeds median %.3f mm / %.3f deg; registered with the board %.3f mm / "
              "%.3f deg (%.3f mm / %.3f deg after the best-fit alignment); without it %.3f mm / %.3f deg; reported "
              "poses %.3f mm / %.3f deg (medians against the truth, unaligned unless said)\n",
              r.poses_from_board, seeded.raw.median_sensor_translation_m * 1e3, seeded.raw.median_rotation_rad / kDeg,
              registered.raw.median_sensor_translation_m * 1e3, registered.raw.median_rotation_rad / kDeg,
              registered.aligned.median_sensor_translation_m * 1e3, registered.aligned.median_rotation_rad / kDeg,
              robot_only.raw.median_sensor_translation_m * 1e3, robot_only.raw.median_rotation_rad / kDeg,
              reported.raw.median_sensor_translation_m * 1e3, reported.raw.median_rotation_rad / kDeg);
  // Measured 1.43 mm / 0.20 deg after the alignment (under 1.0 mm before the
  // joint refinement became the default: it lets the views slide about the
  // cup's axis, which the surface does not fix; issue 35 judges
  // registration by the surface, docs/reconstruction.md).
  EXPECT_LE(registered.aligned.median_sensor_translation_m, 1.6e-3);
  EXPECT_LE(registered.aligned.median_rotation_rad, 0.3 * kDeg);
  // The board fixes the object frame itself: the robot's constant hand-eye
  // error, which registration alone cannot see, mostly drops out.
  EXPECT_LT(registered.raw.median_sensor_translation_m, 0.75 * robot_only.raw.median_sensor_translation_m);
  EXPECT_TRUE(r.registration.graph.converged);
}

TEST(ReconstructionPipeline, BadInputNamesTheFileAndScan) {
  const std::string dir = simulatedRecording(3, true);
  const std::filesystem::path scratch = scratchFolder("pipeline_bad_input");
  // A pose file with too few poses.
  {
    std::ofstream poses(scratch / "short.txt");
    poses << "0 0 0 0 0 0 0 1\n";
  }
  ReconstructionParameters params;
  params.pose_file = (scratch / "short.txt").string();
  params.make_meshes = false;
  try {
    reconstructRawlog(dir + "/scans.rawlog", params);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scan 1"), std::string::npos) << e.what();
  }
  // A crop box the object is not in.
  params = {};
  params.crop_box = Eigen::AlignedBox3d(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6));
  try {
    reconstructRawlog(dir + "/scans.rawlog", params);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scan 0"), std::string::npos) << e.what();
  }
  // A truncated rawlog.
  {
    std::ifstream in(dir + "/scans.rawlog", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream out(scratch / "truncated.rawlog", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  EXPECT_THROW(reconstructRawlog((scratch / "truncated.rawlog").string()), InputError);
  // Board poses without registration: nowhere to put them.
  params = {};
  params.board = BoardLattice{};
  params.register_scans = false;
  EXPECT_THROW(reconstructRawlog(dir + "/scans.rawlog", params), InputError);
  EXPECT_THROW(reconstructRawlog((scratch / "missing.rawlog").string()), InputError);
  std::filesystem::remove_all(scratch);
}

TEST(ReconstructionPipeline, ConvergencePointOfViewsAroundAnObject) {
  std::vector<Eigen::Isometry3d> poses;
  const Eigen::Vector3d target(0.1, -0.2, 0.05);
  for (int i = 0; i < 8; ++i) {
    const double a = 2 * M_PI * i / 8;
    const Eigen::Vector3d eye = target + Eigen::Vector3d(0.7 * std::cos(a), 0.7 * std::sin(a), 0.3);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d forward = (target - eye).normalized();
    const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
    pose.linear().col(0) = forward;  // MRPT: +x along the optical axis
    pose.linear().col(1) = left;
    pose.linear().col(2) = forward.cross(left);
    pose.translation() = eye;
    poses.push_back(pose);
  }
  const auto point = convergencePoint(poses);
  ASSERT_TRUE(point.has_value());
  EXPECT_LT((*point - target).norm(), 1e-9);
  EXPECT_FALSE(convergencePoint({poses.front()}).has_value());
  EXPECT_FALSE(convergencePoint({poses.front(), poses.front()}).has_value());  // parallel axes
}

}  // namespace
}  // namespace icrkit::reconstruction
