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
#include <fstream>
#include <string>

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

// A mobile robot's worst class (8 mm / 2 deg per view, 18-34 mm at the
// object): seed 16 of bench/registration_sweep.py's draws for the 18 real
// views (its start.txt, MRPT sensor axes). The model alignment's four
// levels keep 17, 15, 17 and 17 views: one view is left where the robot put
// it, and the pose graph alone leaves it there. Aligned again after the
// graph against the 17 placed views (`reseat_unplaced_views`), it comes home.
TEST(RealRecordingRegistration, AViewTheModelAlignmentLeftIsReseatedAfterTheGraph) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  const std::string zipper_path = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply";
  for (const std::string& f : {dir + "/scans.rawlog", zipper_path})
    if (!std::filesystem::exists(f)) GTEST_SKIP() << "shared test data not found: " << f;
  // Removed however the test ends.
  struct TemporaryFile {
    std::string path;
    ~TemporaryFile() { std::remove(path.c_str()); }
  } starts{testing::TempDir() + "icrkit_reseat_starts.txt"};
  {
    std::ofstream out(starts.path);
    out << R"(# bench/registration_sweep.py, ps18, 8mm/2deg, seed 16
)"
    "0.000000 0.066921081 0.324987281 0.395391359 -0.569139622 0.692943532 0.338642126 0.285010286\n"
    "1.000000 -0.058652694 0.318707763 0.411170226 0.633325034 -0.609516745 -0.250417582 -0.405807556\n"
    "2.000000 -0.209910844 0.310821466 0.349050978 0.682147755 -0.519793659 -0.149794883 -0.491986266\n"
    "3.000000 -0.320577971 0.302358031 0.278104101 -0.685253875 0.447480274 0.016668070 0.574378539\n"
    "4.000000 -0.402847458 0.318944476 0.133437496 -0.684428239 0.302113873 -0.105711963 0.655065015\n"
    "5.000000 -0.426295526 0.311065545 -0.012614504 -0.658582602 0.181951422 -0.190296373 0.704946755\n"
    "6.000000 -0.410407003 0.298912398 -0.135149033 -0.628207052 0.032568572 -0.331952578 0.702924372\n"
    "7.000000 -0.326746180 0.304713919 -0.259603554 -0.535110342 -0.090734158 -0.432599113 0.719918219\n"
    "8.000000 -0.208463536 0.325734985 -0.347023343 -0.451391719 -0.178147522 -0.526052388 0.698410955\n"
    "9.000000 -0.079868057 0.316654955 -0.392586785 -0.334977849 -0.316034156 -0.586457144 0.666318446\n"
    "10.000000 0.077548478 0.302782010 -0.388501035 -0.248254593 -0.430300866 -0.645748727 0.579844292\n"
    "11.000000 0.202851794 0.321066378 -0.324999127 -0.153612594 -0.507101669 -0.668790872 0.521507275\n"
    "12.000000 0.306956103 0.318127959 -0.231897780 -0.002428234 0.600226753 0.671650307 -0.434290011\n"
    "13.000000 0.368328961 0.290571006 -0.102008174 -0.117095858 0.663004192 0.673802770 -0.304473034\n"
    "14.000000 0.376060926 0.314126513 0.029947679 -0.246566638 0.734164414 0.605788955 -0.182283427\n"
    "15.000000 0.342195762 0.309045243 0.172089452 -0.347610374 0.740411327 0.573196653 -0.049027459\n"
    "16.000000 0.282400611 0.328726472 0.278931996 -0.448525373 0.736992113 0.496286283 0.096786056\n"
    "17.000000 0.167133442 0.324308688 0.382099207 -0.526046653 0.722135577 0.393785456 0.216166930\n";
    ASSERT_TRUE(out.good()) << "cannot write " << starts.path;
  }
  const TriangleMesh zipper = io::readTriangleMesh(zipper_path);
  ReconstructionParameters params;
  params.make_meshes = false;
  params.pose_file = starts.path;
  const ReconstructionResult reseated = reconstructRawlog(dir + "/scans.rawlog", params);
  params.registration.reseat_unplaced_views = false;
  const ReconstructionResult left = reconstructRawlog(dir + "/scans.rawlog", params);
  const double reseated_mm = distanceToBunZipper(reseated.cloud, zipper) * 1e3;
  const double left_mm = distanceToBunZipper(left.cloud, zipper) * 1e3;
  std::printf("8 mm / 2 deg, seed 16: views kept per level %zu %zu %zu %zu; re-seated %zu of %zu tried; fused cloud to "
              "bun_zipper %.3f mm (without the re-seat %.3f mm)\n",
              reseated.registration.model_alignment_accepted.at(0), reseated.registration.model_alignment_accepted.at(1),
              reseated.registration.model_alignment_accepted.at(2), reseated.registration.model_alignment_accepted.at(3),
              reseated.registration.reseat_moved, reseated.registration.reseat_tried, reseated_mm, left_mm);
  EXPECT_GE(reseated.registration.reseat_moved, 1u);
  EXPECT_LT(reseated_mm, 0.8);
  EXPECT_GT(left_mm, reseated_mm + 0.1);
}

}  // namespace
}  // namespace icrkit::reconstruction
