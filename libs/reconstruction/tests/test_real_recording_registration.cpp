// Registration of a real depth-camera recording from poor reported poses:
// the PrimeSense bunny (../shared/data/primesense-bunny), 18 views whose
// sensorPose carries a mobile-manipulator-class error (3 mm / 0.5 deg per
// axis and view), read from the rawlog as it is, judged against the
// Stanford bunny's zipper mesh. Skipped without the data.

#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/registration/trajectory_error.hpp>

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_distance.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/eval/rigid_alignment.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

namespace icrkit::reconstruction {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The fused cloud's mean distance to bun_zipper after a rigid fit (the
// issue-35 measure, gauge-free): what the registration does to the surface.
double distanceToBunZipper(const PointCloud& cloud, const TriangleMesh& zipper) {
  TriangleMesh points;
  points.vertices.positions = cloud.positions;
  const eval::AlignmentResult fit = eval::alignToCad(points, zipper);
  eval::transformMesh(points, fit.transform);
  MeshDistanceParameters every_point;
  every_point.samples = 0;
  return meshDistance(points, zipper, every_point).mean;
}

// Both ways of registering (all views together at the end, or each as it
// arrives) must bring the real recording's views closer to the surface
// they saw than the robot's poses put them. Judged on the surface, as
// issue 35 decided: both pose truths of the recording are imperfect (the
// dataset's places the views 0.84 mm from bun_zipper, the refined one,
// each view fitted to bun_zipper alone, 0.41 mm, and the two disagree by
// about 2 deg between views 90 deg apart), so the pose errors against both
// are printed, never a gate.
void checkPrimeSenseBunny(bool incremental) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  const std::string zipper_path = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply";
  for (const std::string& f : {dir + "/scans.rawlog", dir + "/ground_truth.txt", dir + "/ground_truth_refined.txt",
                               zipper_path})
    if (!std::filesystem::exists(f)) GTEST_SKIP() << "shared test data not found: " << f;
  const TriangleMesh zipper = io::readTriangleMesh(zipper_path);
  ReconstructionParameters params;
  params.make_meshes = false;
  params.registration.incremental = incremental;
  const ReconstructionResult r = reconstructRawlog(dir + "/scans.rawlog", params);
  ReconstructionParameters robot = params;
  robot.register_scans = false;
  robot.registration.incremental = false;
  const ReconstructionResult at_reported = reconstructRawlog(dir + "/scans.rawlog", robot);
  // Its stored rotation matrices are off by up to 8.5e-3: projected, counted.
  EXPECT_EQ(r.poses_orthonormalised, r.poses.size());
  const Eigen::Vector3d centre = r.crop_box.center();
  for (const char* truth_file : {"/ground_truth.txt", "/ground_truth_refined.txt"}) {
    std::vector<Eigen::Isometry3d> truth;
    for (const StampedPose& p : readTumTrajectory(dir + truth_file)) truth.push_back(p.pose);
    ASSERT_EQ(truth.size(), r.poses.size());
    const TrajectoryError registered = trajectoryError(r.poses, truth, centre);
    const TrajectoryError reported = trajectoryError(r.reported_poses, truth, centre);
    std::printf("against %s, aligned median at the object: reported %.2f mm %.3f deg -> registered %.2f mm %.3f deg "
                "(max %.2f mm)\n",
                truth_file + 1, reported.aligned.median_object_translation_m * 1e3,
                reported.aligned.median_rotation_rad / kDeg, registered.aligned.median_object_translation_m * 1e3,
                registered.aligned.median_rotation_rad / kDeg, registered.aligned.max_object_translation_m * 1e3);
  }
  const double registered_mm = distanceToBunZipper(r.cloud, zipper) * 1e3;
  const double reported_mm = distanceToBunZipper(at_reported.cloud, zipper) * 1e3;
  std::printf("fused cloud to bun_zipper after a fit: reported poses %.3f mm -> registered %.3f mm; joint refinement "
              "%s (%zu of the graph's %zu pairs of views linked); %zu pairs, odometry sigma measured %.2f mm %.3f "
              "deg; %.0f ms\n",
              reported_mm, registered_mm, r.registration.joint_applied ? "kept" : r.registration.joint_rejection.c_str(),
              r.registration.joint_linked_view_pairs, r.registration.joint_graph_view_pairs,
              r.registration.pairs.size(), r.registration.measured_odometry_sigma_translation_m * 1e3,
              r.registration.measured_odometry_sigma_rotation_rad / kDeg, r.times.registration_ms);
  // Measured 2.77 mm at the reported poses; registered 0.70 either way
  // (0.73 without the joint refinement). Against the refined truth the
  // joint brings the views from 7.8 to 3.8 mm at the object (median),
  // against the dataset's it moves them from 2.5 to 5.1 mm.
  EXPECT_LT(registered_mm, 0.5 * reported_mm);
  EXPECT_LT(registered_mm, 0.8);
  EXPECT_TRUE(r.registration.joint_applied) << r.registration.joint_rejection;
  // The robot's precision measured from the data: independent per-view
  // errors, far beyond the arm defaults (0.5 mm / 0.057 deg).
  EXPECT_GT(r.registration.measured_odometry_sigma_translation_m, 2e-3);
  EXPECT_GT(r.registration.odometry_sigma_translation_m, 2e-3);
}

TEST(RealRecordingRegistration, PrimeSenseBunnyFromItsReportedPoses) { checkPrimeSenseBunny(false); }

TEST(RealRecordingRegistration, PrimeSenseBunnyRegisteredAsTheScansArrive) { checkPrimeSenseBunny(true); }

}  // namespace
}  // namespace icrkit::reconstruction
