// Registration of a real depth-camera recording from poor reported poses:
// the PrimeSense bunny (../shared/data/primesense-bunny), 18 views whose
// sensorPose carries a mobile-manipulator-class error (3 mm / 0.5 deg per
// axis and view), read from the rawlog as it is, judged against the
// Stanford bunny's zipper mesh. Skipped without the data.

#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>
#include <icrkit/reconstruction/registration/trajectory_error.hpp>

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_distance.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/eval/rigid_alignment.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
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

// Starting poses from a start.txt's text (TUM lines; '#' lines skipped).
std::vector<Eigen::Isometry3d> parseStarts(const std::string& starts_text) {
  std::istringstream text(starts_text);
  std::vector<Eigen::Isometry3d> starts;
  std::size_t line_number = 0;
  for (std::string line; std::getline(text, line);) {
    ++line_number;
    if (!line.empty() && line[0] != '#') starts.push_back(parseTumLine(line, "the starts", line_number).pose);
  }
  return starts;
}

// Every `stride`-th point of the views, placed by `poses`, fused: its
// distance to bun_zipper after a fit (mm).
double placedViewsToBunZipperMm(const std::vector<PointCloud>& views, const std::vector<Eigen::Isometry3d>& poses,
                                const TriangleMesh& zipper, std::size_t stride) {
  PointCloud fused;
  for (std::size_t i = 0; i < views.size(); ++i)
    for (std::size_t k = 0; k < views[i].positions.size(); k += stride)
      fused.positions.push_back(poses[i] * views[i].positions[k]);
  return distanceToBunZipper(fused, zipper) * 1e3;
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
  // The bunny's size as its views see it (45.5 mm; bun_zipper's vertices,
  // the whole bunny, 48 mm): every level of the model alignment is kept,
  // the 6 cm one included.
  if (!incremental) {
    EXPECT_NEAR(r.registration.model_spread_m, 0.045, 0.004);
    EXPECT_EQ(r.registration.model_alignment_resolutions, params.registration.model_alignment_resolutions);
  } else {
    EXPECT_EQ(r.registration.model_spread_m, 0.0);
  }
}

TEST(RealRecordingRegistration, PrimeSenseBunnyFromItsReportedPoses) { checkPrimeSenseBunny(false); }

TEST(RealRecordingRegistration, PrimeSenseBunnyRegisteredAsTheScansArrive) { checkPrimeSenseBunny(true); }

// A mobile robot's worst class (8 mm / 2 deg per view, 18-34 mm at the
// object) on the shared rawlog: starting poses drawn by
// bench/registration_sweep.py for the 18 real views (a run's start.txt,
// MRPT sensor axes) replace the reported ones. Returns the fused cloud's
// distance to bun_zipper (mm) at the defaults and with `without` applied,
// and the default run's registration; nullopt without the data.
struct StartsOutcome {
  double default_mm = 0.0, without_mm = 0.0;
  SequenceRegistrationResult registration;
};
std::optional<StartsOutcome> reconstructFromStarts(const std::string& name, const std::string& starts_text,
                                                   void (*without)(SequenceRegistrationParameters&)) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  const std::string zipper_path = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply";
  for (const std::string& f : {dir + "/scans.rawlog", zipper_path})
    if (!std::filesystem::exists(f)) return std::nullopt;
  // Removed however the test ends.
  struct TemporaryFile {
    std::string path;
    ~TemporaryFile() { std::remove(path.c_str()); }
  } starts{testing::TempDir() + "icrkit_" + name + "_starts.txt"};
  {
    std::ofstream out(starts.path);
    out << starts_text;
    if (!out.good()) throw std::runtime_error("cannot write " + starts.path);
  }
  const TriangleMesh zipper = io::readTriangleMesh(zipper_path);
  ReconstructionParameters params;
  params.make_meshes = false;
  params.pose_file = starts.path;
  const ReconstructionResult with = reconstructRawlog(dir + "/scans.rawlog", params);
  without(params.registration);
  const ReconstructionResult left = reconstructRawlog(dir + "/scans.rawlog", params);
  return StartsOutcome{distanceToBunZipper(with.cloud, zipper) * 1e3, distanceToBunZipper(left.cloud, zipper) * 1e3,
                       with.registration};
}

// Seed 16: the model alignment's four levels keep 17, 15, 17 and 17 views:
// one view is left where the robot put it, and the pose graph alone leaves
// it there. Aligned again after the graph against the 17 placed views
// (`reseat_unplaced_views`), it comes home.
TEST(RealRecordingRegistration, AViewTheModelAlignmentLeftIsReseatedAfterTheGraph) {
  const auto outcome = reconstructFromStarts("reseat",
    "# bench/registration_sweep.py, ps18, 8mm/2deg, seed 16\n"
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
    "17.000000 0.167133442 0.324308688 0.382099207 -0.526046653 0.722135577 0.393785456 0.216166930\n",
      [](SequenceRegistrationParameters& p) { p.reseat_unplaced_views = false; });
  if (!outcome) GTEST_SKIP() << "shared test data not found under " << ICRKIT_SHARED_DATA_DIR;
  const SequenceRegistrationResult& r = outcome->registration;
  std::printf("8 mm / 2 deg, seed 16: views kept per level %zu %zu %zu %zu; re-seated %zu of %zu tried; fused cloud to "
              "bun_zipper %.3f mm (without the re-seat %.3f mm)\n",
              r.model_alignment_accepted.at(0), r.model_alignment_accepted.at(1), r.model_alignment_accepted.at(2),
              r.model_alignment_accepted.at(3), r.reseat_moved, r.reseat_tried, outcome->default_mm,
              outcome->without_mm);
  EXPECT_GE(r.reseat_moved, 1u);
  EXPECT_LT(outcome->default_mm, 0.8);
  EXPECT_GT(outcome->without_mm, outcome->default_mm + 0.1);
}

// Seed 9: every start of the re-seat's level walk turns one view 30 deg
// round the bunny (rejected by the rotation limit), so the graph's pose, a
// view 25 mm off that shares 5 % of its cubes with the others, would stay.
// The grid of starts around it (`reseat_search_step`) finds it home.
TEST(RealRecordingRegistration, AViewLeftApartIsSearchedForAroundItsGraphPose) {
  const auto outcome = reconstructFromStarts("search",
    "# bench/registration_sweep.py, ps18, 8mm/2deg, seed 9\n"
    "0.000000 0.073228861 0.327554427 0.396913588 -0.583455602 0.668965403 0.366475958 0.278855199\n"
    "1.000000 -0.074865394 0.326887671 0.393060040 0.642770404 -0.610417160 -0.254999573 -0.386280101\n"
    "2.000000 -0.213373692 0.313592244 0.364829072 0.688967000 -0.526464982 -0.128804599 -0.481215618\n"
    "3.000000 -0.338035061 0.315681256 0.270285410 -0.725462933 0.406546828 0.032974067 0.554378860\n"
    "4.000000 -0.399034535 0.315153271 0.144965782 -0.660008160 0.309925115 -0.101326461 0.676807654\n"
    "5.000000 -0.430607042 0.314817622 -0.017203335 -0.679676367 0.158442785 -0.222369422 0.680799354\n"
    "6.000000 -0.388825084 0.320834386 -0.145667814 -0.578105177 0.065507688 -0.357784398 0.730406375\n"
    "7.000000 -0.313989376 0.315234671 -0.282343059 -0.537602219 -0.053847732 -0.412592775 0.733383582\n"
    "8.000000 -0.202158904 0.319411425 -0.343692603 -0.440842719 -0.212505270 -0.531529696 0.691357643\n"
    "9.000000 -0.077862868 0.308442538 -0.403994820 -0.351849997 -0.330009878 -0.579222466 0.657112164\n"
    "10.000000 0.070828506 0.305615640 -0.394011615 -0.259540073 -0.443286523 -0.612039845 0.601284655\n"
    "11.000000 0.203182379 0.307983376 -0.341160139 0.100964030 0.532543622 0.696565040 -0.470107116\n"
    "12.000000 0.313559578 0.313607917 -0.235971088 0.007886531 0.591139712 0.691801531 -0.414611005\n"
    "13.000000 0.389248316 0.300904081 -0.105711612 -0.095625524 0.669268130 0.678630914 -0.287047056\n"
    "14.000000 0.388690092 0.327158557 0.032853044 -0.213583272 0.714791422 0.637919509 -0.191086654\n"
    "15.000000 0.343541557 0.330369139 0.174973747 -0.328328400 0.742279172 0.582985448 -0.036743150\n"
    "16.000000 0.264114325 0.320619048 0.287906104 -0.459436636 0.710056477 0.530547043 0.057075494\n"
    "17.000000 0.149754415 0.320384788 0.389755438 -0.540034694 0.694541412 0.412428490 0.236384216\n",
      [](SequenceRegistrationParameters& p) { p.reseat_search_step = 0; });
  if (!outcome) GTEST_SKIP() << "shared test data not found under " << ICRKIT_SHARED_DATA_DIR;
  const SequenceRegistrationResult& r = outcome->registration;
  std::printf("8 mm / 2 deg, seed 9: re-seated %zu of %zu tried, %zu searched for; fused cloud to bun_zipper %.3f mm "
              "(without the search %.3f mm)\n",
              r.reseat_moved, r.reseat_tried, r.reseat_searched, outcome->default_mm, outcome->without_mm);
  EXPECT_GE(r.reseat_searched, 1u);
  EXPECT_LT(outcome->default_mm, 0.8);
  EXPECT_GT(outcome->without_mm, outcome->default_mm + 0.5);
}

// Ten Stanford laser scans of the bunny in their sensors' frames (as
// bench/registration_sweep.py places them: 0.6 m up the scanner's +z,
// looking down), from seed 10 of its 8 mm / 2 deg draws (a start.txt).
// bun180 and ear_back, both of the bunny's back, end 22 mm off together:
// they agree with each other (0.67-0.80 of their cubes shared) and with
// nobody else (0.00-0.06), so neither looks apart alone. Outside the
// largest group of linked views, they are re-seated against the others as
// one rigid group.
TEST(RealRecordingRegistration, TwoScansOffTogetherAreReseatedAsOutsideTheLinkedGroup) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny";
  const std::vector<std::string> order{"bun000.ply", "bun045.ply", "bun090.ply",   "bun180.ply", "bun270.ply",
                                       "bun315.ply", "chin.ply",   "ear_back.ply", "top2.ply",   "top3.ply"};
  for (const std::string& name : order)
    if (!std::filesystem::exists(dir + "/" + name)) GTEST_SKIP() << "shared test data not found: " << dir << "/" << name;
  Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();  // sensor frame -> scan frame
  sensor.linear() << 0, -1, 0, 0, 0, 1, -1, 0, 0;
  sensor.translation() = Eigen::Vector3d(-0.017, 0.11, 0.6);
  std::vector<PointCloud> views;
  for (const std::string& name : order) {
    PointCloud scan = io::readPointCloud(dir + "/" + name);
    for (Eigen::Vector3d& p : scan.positions) p = sensor.inverse() * p;
    scan.normals.clear();
    views.push_back(std::move(scan));
  }
  const std::vector<Eigen::Isometry3d> starts = parseStarts(
      "0.000000 -0.004101297 0.109759784 0.601880665 -0.507690738 0.468101849 0.517341839 0.505458402\n"
      "1.000000 0.280368730 0.100824699 0.498547498 -0.310571433 0.617785440 0.647142529 0.321081115\n"
      "2.000000 0.591933107 0.114091452 0.007149518 0.015394294 0.720084244 0.693669561 -0.008014877\n"
      "3.000000 0.010548524 0.113951531 -0.596929646 0.537735848 0.508350194 0.471073743 -0.480114327\n"
      "4.000000 -0.596937995 0.105099570 -0.012247675 -0.696456595 -0.003252244 -0.025053531 0.717154066\n"
      "5.000000 -0.442270608 0.112723226 0.397398755 -0.650834999 0.280276937 0.269902580 0.651928861\n"
      "6.000000 -0.264708837 -0.300033789 0.284325017 -0.307876792 0.139564124 0.535618891 0.773851497\n"
      "7.000000 0.277203035 -0.146193483 -0.389066599 0.513406740 0.651556952 0.541861046 -0.135180119\n"
      "8.000000 0.128375210 0.458992388 -0.376314301 -0.549439960 0.752713733 -0.311439942 -0.185857281\n"
      "9.000000 0.238425352 0.588264114 0.089551077 -0.151915000 0.117343789 0.847334385 -0.495153217\n");
  ASSERT_EQ(starts.size(), views.size());
  const TriangleMesh zipper = io::readTriangleMesh(dir + "/bun_zipper.ply");
  SequenceRegistrationParameters params = ReconstructionParameters{}.registration;
  const SequenceRegistrationResult grouped = registerScanSequence(views, starts, params);
  params.reseat_min_pair_cubes = 0;
  const SequenceRegistrationResult alone = registerScanSequence(views, starts, params);
  const double grouped_mm = placedViewsToBunZipperMm(views, grouped.poses, zipper, 4),
               alone_mm = placedViewsToBunZipperMm(views, alone.poses, zipper, 4);
  std::printf("Stanford scans, 8 mm / 2 deg, seed 10: re-seated %zu of %zu tried; fused scans to bun_zipper %.3f mm "
              "(without the groups %.3f mm)\n",
              grouped.reseat_moved, grouped.reseat_tried, grouped_mm, alone_mm);
  EXPECT_EQ(grouped.reseat_tried, 2u);
  EXPECT_LT(grouped_mm, 0.3);
  EXPECT_GT(alone_mm, 3.0);
}

// Nine of the real views (every other one, 40 deg apart), as the sweep
// prepares them (bench/registration_sweep.py: cropped at the dataset's
// poses, in their sensors' frames), registered from `starts_text` (a
// start.txt of the sweep's 8 mm / 2 deg draws on that subset: up to 50 mm
// at the object between neighbours) at the defaults with `base` applied,
// and with `without` applied too; nullopt without the data. Prepared once
// for every test.
std::optional<StartsOutcome> registerNineViewsFromStarts(const std::string& starts_text,
                                                         void (*base)(SequenceRegistrationParameters&),
                                                         void (*without)(SequenceRegistrationParameters&)) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  const std::string zipper_path = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply";
  for (const std::string& f : {dir + "/scans.rawlog", dir + "/ground_truth.txt", zipper_path})
    if (!std::filesystem::exists(f)) return std::nullopt;
  static const std::vector<PointCloud> views = [&] {
    ReconstructionParameters prepare;
    prepare.make_meshes = false;
    prepare.keep_registration_input = true;
    prepare.pose_file = dir + "/ground_truth.txt";
    const ReconstructionResult prepared = reconstructRawlog(dir + "/scans.rawlog", prepare);
    std::vector<PointCloud> even;
    for (std::size_t i = 0; i < prepared.registration_input.size(); i += 2)
      even.push_back(prepared.registration_input[i]);
    return even;
  }();
  static const TriangleMesh zipper = io::readTriangleMesh(zipper_path);
  if (views.size() != 9) throw std::runtime_error("expected 18 real views, found " + std::to_string(2 * views.size()));
  const std::vector<Eigen::Isometry3d> starts = parseStarts(starts_text);
  if (starts.size() != views.size()) throw std::runtime_error("expected nine starting poses");
  SequenceRegistrationParameters params = ReconstructionParameters{}.registration;
  base(params);
  StartsOutcome outcome;
  outcome.registration = registerScanSequence(views, starts, params);
  outcome.default_mm = placedViewsToBunZipperMm(views, outcome.registration.poses, zipper, 1);
  without(params);
  outcome.without_mm = placedViewsToBunZipperMm(views, registerScanSequence(views, starts, params).poses, zipper, 1);
  return outcome;
}

// The two tests below show their step alone, without the unsettled round
// (`max_unsettled_rounds`, later than they): on seed 8 that round links
// the group too (the third test).
void withoutUnsettledRounds(SequenceRegistrationParameters& p) { p.max_unsettled_rounds = 0; }

// Seed 10: the model alignment places all nine, but as two groups, each
// against itself: views 7, 8, 0, 1 and 3-6 agree within each group and
// lie about a centimetre apart (view 2 between). Their linking pairs
// start with the ICP alone (both views placed), which finds too little
// overlap and rejects them; the groups are four and four, so neither is
// re-seated against a majority. No accepted pair joins the groups, so
// those the ICP matched too little of (their views beyond its reach) are
// registered again with the pair's NDT first, and one of them links them.
TEST(RealRecordingRegistration, ARejectedPairOfPlacedViewsIsRetriedWithTheCoarseStart) {
  const auto outcome = registerNineViewsFromStarts(
      "# bench/registration_sweep.py, ps9, 8mm/2deg, seed 10\n"
      "0.000000 0.054011059 0.323946681 0.409275085 -0.575884915 0.680586097 0.366958995 0.265518785\n"
      "1.000000 -0.218552066 0.324150548 0.364158222 0.693888133 -0.545556067 -0.129277860 -0.451857357\n"
      "2.000000 -0.391822753 0.316849242 0.138048964 -0.653523173 0.281565033 -0.130882071 0.690288692\n"
      "3.000000 -0.407924395 0.312308140 -0.146048121 -0.623982799 0.058782120 -0.307431237 0.716014080\n"
      "4.000000 -0.201570322 0.309302102 -0.354576305 -0.464861616 -0.205508221 -0.534420039 0.675326048\n"
      "5.000000 0.072697205 0.302127310 -0.386715387 -0.224990331 -0.447274444 -0.641589657 0.581108970\n"
      "6.000000 0.312705766 0.305692999 -0.248290177 -0.004299366 0.627879927 0.673555934 -0.389962456\n"
      "7.000000 0.387499123 0.302323268 0.044817233 -0.248217683 0.703727674 0.647358632 -0.155184229\n"
      "8.000000 0.272299919 0.324758764 0.293126522 -0.428669848 0.748685046 0.503221799 0.049806475\n",
      withoutUnsettledRounds, [](SequenceRegistrationParameters& p) { p.pair_ndt_retry_rejected = false; });
  if (!outcome) GTEST_SKIP() << "shared test data not found under " << ICRKIT_SHARED_DATA_DIR;
  const SequenceRegistrationResult& r = outcome->registration;
  std::printf(
      "9 real views, 8 mm / 2 deg, seed 10: %zu rejected pairs retried with the coarse start, %zu accepted; "
      "fused views to bun_zipper %.3f mm (without the retry %.3f mm)\n",
      r.pairs_retried_coarse, r.pairs_retried_accepted, outcome->default_mm, outcome->without_mm);
  EXPECT_GE(r.pairs_retried_accepted, 1u);
  EXPECT_LT(outcome->default_mm, 0.8);
  EXPECT_GT(outcome->without_mm, outcome->default_mm + 3.0);
}

// The sweep's start.txt of ps9, 8 mm / 2 deg, seed 8.
const char* const kNineViewsSeed8Starts =
    "# bench/registration_sweep.py, ps9, 8mm/2deg, seed 8\n"
    "0.000000 0.063351214 0.319839502 0.398602638 -0.582676960 0.671148182 0.352748481 0.292602440\n"
    "1.000000 -0.215297109 0.313146084 0.369053549 0.668371863 -0.534618137 -0.141974690 -0.497298389\n"
    "2.000000 -0.385196066 0.313901054 0.134751979 -0.657248200 0.323346806 -0.085040609 0.675455211\n"
    "3.000000 -0.401565297 0.313820729 -0.144393417 -0.600983920 0.053201097 -0.316346738 0.732060594\n"
    "4.000000 -0.193740998 0.299149839 -0.346546327 -0.451645894 -0.204076327 -0.519059518 0.696380683\n"
    "5.000000 0.071777786 0.318596713 -0.379467944 -0.244783305 -0.435217599 -0.634881731 0.589569302\n"
    "6.000000 0.320442179 0.313964769 -0.230783007 -0.012487397 0.606162506 0.676813527 -0.417533869\n"
    "7.000000 0.386171647 0.321843777 0.034684684 -0.222170012 0.715906874 0.644673125 -0.150047975\n"
    "8.000000 0.259468492 0.325204208 0.287741729 -0.443955951 0.716063665 0.527670703 0.108256963\n";

// Seed 8: after the graph views 3-5 (linked to each other) lie 12-14 mm
// from the other six, and view 6, between them, is apart alone. Against
// views 7, 8, 0, 1 and 2 alone no start seats the group (its only wide
// overlap is with view 6); view 6 is seated by the search. The second
// pass aligns the group against those six and view 6.
TEST(RealRecordingRegistration, AGroupNoStartSeatsIsAlignedAgainAfterTheOthersAreSeated) {
  const auto outcome = registerNineViewsFromStarts(
      kNineViewsSeed8Starts,
      withoutUnsettledRounds, [](SequenceRegistrationParameters& p) { p.reseat_passes = 1; });
  if (!outcome) GTEST_SKIP() << "shared test data not found under " << ICRKIT_SHARED_DATA_DIR;
  const SequenceRegistrationResult& r = outcome->registration;
  std::printf(
      "9 real views, 8 mm / 2 deg, seed 8: re-seated %zu of %zu tried, %zu searched for; fused views to "
      "bun_zipper %.3f mm (one pass %.3f mm)\n",
      r.reseat_moved, r.reseat_tried, r.reseat_searched, outcome->default_mm, outcome->without_mm);
  EXPECT_EQ(r.reseat_tried, 4u);
  EXPECT_LT(outcome->default_mm, 1.0);
  EXPECT_GT(outcome->without_mm, outcome->default_mm + 2.0);
}

// Seed 8 again: the second round's graph moved views 3-6 by up to 24 mm,
// and four pairs the ICP had matched too little of (0-12 %), between views
// the accepted pairs leave apart, now have their views 9-34 mm elsewhere
// relative to each other. The pairs between the groups (those and the
// ones chosen anew at the graph's poses) are registered from there and
// one links the group: a third round. With one re-seat pass (which alone
// leaves the group apart) it brings them home.
TEST(RealRecordingRegistration, AGroupTheSecondRoundMovedFarIsLinkedByAThird) {
  const auto outcome = registerNineViewsFromStarts(
      kNineViewsSeed8Starts,
      [](SequenceRegistrationParameters& p) { p.reseat_passes = 1; }, withoutUnsettledRounds);
  if (!outcome) GTEST_SKIP() << "shared test data not found under " << ICRKIT_SHARED_DATA_DIR;
  const SequenceRegistrationResult& r = outcome->registration;
  std::printf("9 real views, 8 mm / 2 deg, seed 8: %d rounds, %zu pairs registered for the third, %zu accepted; "
              "fused views to bun_zipper %.3f mm (two rounds %.3f mm)\n",
              r.refinement_rounds, r.unsettled_pairs_registered, r.unsettled_pairs_accepted, outcome->default_mm,
              outcome->without_mm);
  EXPECT_EQ(r.refinement_rounds, 3);
  EXPECT_GE(r.unsettled_pairs_accepted, 1u);
  EXPECT_LT(outcome->default_mm, 1.0);
  EXPECT_GT(outcome->without_mm, outcome->default_mm + 2.0);
  // A round count given explicitly is kept: no pair is registered for an
  // unsettled round.
  const auto given = registerNineViewsFromStarts(
      kNineViewsSeed8Starts,
      [](SequenceRegistrationParameters& p) {
        p.reseat_passes = 1;
        p.refinement_rounds = 2;
      },
      withoutUnsettledRounds);
  ASSERT_TRUE(given);
  EXPECT_EQ(given->registration.refinement_rounds, 2);
  EXPECT_EQ(given->registration.unsettled_pairs_registered, 0u);
  EXPECT_DOUBLE_EQ(given->default_mm, given->without_mm);
}

}  // namespace
}  // namespace icrkit::reconstruction
