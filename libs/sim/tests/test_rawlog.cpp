#include <icrkit/sim/acquisition.hpp>
#include <icrkit/sim/range_sensor.hpp>
#include <icrkit/sim/rawlog_writer.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CRawlog.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>
#include <string>

namespace icrkit::sim {
namespace {

namespace fs = std::filesystem;

// A sensor model with just what the writer reads: a small pinhole camera.
SensorModel pinhole(bool range_is_depth) {
  SensorModel m;
  m.type = range_is_depth ? SensorType::Kinect : SensorType::Sr4000;
  m.intrinsics.width = 64;
  m.intrinsics.height = 48;
  m.intrinsics.fx = m.intrinsics.fy = 60.0;
  m.intrinsics.cx = 31.5;
  m.intrinsics.cy = 23.5;
  m.range_is_depth = range_is_depth;
  m.range_units = 0.0001;
  m.min_range = 0.1;
  m.max_range = 5.0;
  m.name = "test pinhole";
  return m;
}

// An ideal scan: each pixel's ray (through the pixel centre at integer
// coordinates, OpenCV's and MRPT's convention) hits the scene exactly.
SimulatedScan idealScan(const RayCaster& caster, const Eigen::Isometry3d& camera, const SensorModel& m) {
  SimulatedScan s;
  s.width = m.intrinsics.width;
  s.height = m.intrinsics.height;
  const auto n = static_cast<std::size_t>(s.width * s.height);
  s.range.assign(n, 0.0f);
  s.true_range.assign(n, 0.0f);
  s.true_face.assign(n, -1);
  s.confidence.assign(n, 200);
  s.intensity.assign(n, 100);
  for (int r = 0; r < s.height; ++r)
    for (int c = 0; c < s.width; ++c) {
      const Eigen::Vector3d d((c - m.intrinsics.cx) / m.intrinsics.fx, (r - m.intrinsics.cy) / m.intrinsics.fy, 1.0);
      Ray ray;
      ray.origin = camera.translation();
      ray.direction = camera.linear() * d;
      const RayHit hit = caster.closestHit(ray);
      if (!hit.hit) continue;
      const std::size_t p = static_cast<std::size_t>(r * s.width + c);
      s.range[p] = static_cast<float>(m.range_is_depth ? hit.distance / d.norm() : hit.distance);
      s.true_range[p] = s.range[p];
      s.true_face[p] = hit.face;
    }
  return s;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class RawlogRoundTrip : public ::testing::TestWithParam<bool> {};

// The whole convention at once: MRPT reads the file, and its own
// unprojection with the written sensorPose puts every pixel back on the
// surface it came from (within the range quantisation).
TEST_P(RawlogRoundTrip, MrptUnprojectsOntoTheScannedSurface) {
  const bool range_is_depth = GetParam();
  const TriangleMesh sphere = makeIcosphere(4, 0.05, Eigen::Vector3d(0, 0, 0.05));
  const RayCaster caster(sphere);
  AcquisitionParameters params;
  params.setup = sim::Setup::A;
  params.views = 3;
  params.distance = 0.4;
  params.errors = perfectPoses();
  const std::vector<View> views = planViews(params, sphere.vertices.bounds());
  const SensorModel model = pinhole(range_is_depth);
  std::vector<SimulatedScan> scans;
  for (const View& v : views) scans.push_back(idealScan(caster, v.true_camera, model));

  const fs::path dir = fs::temp_directory_path() / ("icrkit_rawlog_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "scans.rawlog").string();
  writeRawlog(path, model, scans, views);
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  mrpt::obs::CRawlog rawlog;
  ASSERT_TRUE(rawlog.loadFromRawLogFile(path));
  ASSERT_EQ(rawlog.size(), views.size());
  std::size_t checked = 0;
  double worst = 0;
  for (std::size_t i = 0; i < rawlog.size(); ++i) {
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(rawlog.getAsObservation(i));
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->range_is_depth, range_is_depth);
    EXPECT_FLOAT_EQ(obs->rangeUnits, 0.0001f);
    EXPECT_EQ(obs->sensorLabel, range_is_depth ? "KINECT" : "SR4000");
    EXPECT_EQ(obs->rangeImage.cols(), 64);
    EXPECT_EQ(obs->rangeImage.rows(), 48);
    EXPECT_TRUE(obs->hasIntensityImage);
    EXPECT_TRUE(obs->hasConfidenceImage);
    EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), kRawlogEpoch + views[i].timestamp, 1e-6);
    mrpt::maps::CSimplePointsMap points;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    obs->unprojectInto(points, pp);
    ASSERT_GT(points.size(), 100u);
    for (std::size_t k = 0; k < points.size(); ++k) {
      float x, y, z;
      points.getPoint(k, x, y, z);
      const ClosestPoint cp = caster.closestPoint(Eigen::Vector3d(x, y, z));
      worst = std::max(worst, cp.distance);
      ++checked;
    }
  }
  // 0.05 mm quantisation plus single precision in MRPT's unprojection.
  EXPECT_LT(worst, 2e-4) << checked << " points";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(DepthAndRange, RawlogRoundTrip, ::testing::Values(true, false));

TEST(Rawlog, SameInputSameBytes) {
  const TriangleMesh sphere = makeIcosphere(3, 0.05, Eigen::Vector3d(0, 0, 0.05));
  const RayCaster caster(sphere);
  AcquisitionParameters params;
  params.views = 2;
  const std::vector<View> views = planViews(params, sphere.vertices.bounds());
  const SensorModel model = pinhole(true);
  std::vector<SimulatedScan> scans;
  for (const View& v : views) scans.push_back(idealScan(caster, v.true_camera, model));
  const fs::path dir = fs::temp_directory_path() / ("icrkit_rawlog_bytes_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  writeRawlog((dir / "a.rawlog").string(), model, scans, views);
  writeRawlog((dir / "b.rawlog").string(), model, scans, views);
  EXPECT_EQ(readBytes((dir / "a.rawlog").string()), readBytes((dir / "b.rawlog").string()));
  // An unwritable place: a clear error, nothing left behind.
  EXPECT_THROW(writeRawlog((dir / "missing" / "c.rawlog").string(), model, scans, views), InputError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
  fs::remove_all(dir);
}

TEST(Acquisition, ViewsLookAtTheObjectFromTheSetupsDistance) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.04, -0.04, 0), Eigen::Vector3d(0.04, 0.04, 0.1));
  for (sim::Setup setup : {sim::Setup::A, sim::Setup::B}) {
    AcquisitionParameters params;
    params.setup = setup;
    params.views = 12;
    params.errors = perfectPoses();
    const std::vector<View> views = planViews(params, box);
    ASSERT_EQ(views.size(), 12u);
    for (const View& v : views) {
      const Eigen::Vector3d to_centre = box.center() - v.true_camera.translation();
      EXPECT_NEAR(to_centre.norm(), setup == sim::Setup::A ? 0.6 : 0.7, 1e-12);
      // The optical axis points at the centre; image "down" has no +z part.
      EXPECT_NEAR(v.true_camera.linear().col(2).dot(to_centre.normalized()), 1.0, 1e-12);
      EXPECT_LE(v.true_camera.linear().col(1).z(), 0.0);
      EXPECT_NEAR(v.true_camera.linear().determinant(), 1.0, 1e-12);
      EXPECT_TRUE(v.reported_camera.isApprox(v.true_camera, 1e-12));
    }
    if (setup == sim::Setup::B) {
      // One turn of the flange, evenly.
      const double step = std::atan2(views[1].true_camera.translation().y(), views[1].true_camera.translation().x()) -
                          std::atan2(views[0].true_camera.translation().y(), views[0].true_camera.translation().x());
      EXPECT_NEAR(step, 2 * M_PI / 12, 1e-12);
    }
  }
}

TEST(Acquisition, ReportedPosesCarryTheModelledErrors) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.04, -0.04, 0), Eigen::Vector3d(0.04, 0.04, 0.1));
  AcquisitionParameters params;
  params.views = 36;
  const std::vector<View> a = planViews(params, box);
  const std::vector<View> b = planViews(params, box);
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a[i].reported_camera.isApprox(b[i].reported_camera, 0.0));  // deterministic
    const double offset = (a[i].reported_camera.translation() - a[i].true_camera.translation()).norm();
    sum += offset;
    // Hand-eye offset 2 mm, drift up to 35 x 0.05 mm, noise 0.3 mm per axis.
    EXPECT_LT(offset, 0.002 + 35 * 0.00005 + 5 * 0.0003 * std::sqrt(3.0));
  }
  EXPECT_GT(sum / a.size(), 0.001);
  params.seed = 2;
  EXPECT_FALSE(planViews(params, box)[0].reported_camera.isApprox(a[0].reported_camera, 1e-9));
  params.views = 0;
  EXPECT_THROW(planViews(params, box), InputError);
  EXPECT_THROW(parseSetup("C"), InputError);
  EXPECT_EQ(parseSetup("a"), sim::Setup::A);
}

TEST(Acquisition, SceneHoldsTheObjectAndTheFixtures) {
  const TriangleMesh sphere = makeIcosphere(2, 0.05, Eigen::Vector3d(0, 0, 0.05));
  for (sim::Setup setup : {sim::Setup::A, sim::Setup::B}) {
    const Scene scene = buildScene(sphere, setup);
    EXPECT_EQ(scene.object_faces, sphere.faces.size());
    EXPECT_GT(scene.mesh.faces.size(), sphere.faces.size());
    scene.mesh.vertices.validate();
    // A ray straight down next to the object hits the fixture's top just below z = 0.
    const RayCaster caster(scene.mesh);
    Ray ray;
    ray.origin = Eigen::Vector3d(0.055, 0.0, 0.5);
    ray.direction = -Eigen::Vector3d::UnitZ();
    const RayHit hit = caster.closestHit(ray);
    ASSERT_TRUE(hit.hit);
    EXPECT_GE(static_cast<std::size_t>(hit.face), scene.object_faces);
    EXPECT_NEAR(hit.point.z(), -1e-4, 1e-9);
    ASSERT_TRUE(scene.appearance.colour && scene.appearance.reflectivity);
    if (setup == sim::Setup::B) {
      // The checkerboard: 2 cm squares alternate dark and light.
      const Colour a = scene.appearance.colour(hit.face, Eigen::Vector3d(0.01, 0.01, 0));
      const Colour b = scene.appearance.colour(hit.face, Eigen::Vector3d(0.03, 0.01, 0));
      EXPECT_NE(a, b);
    }
  }
}

}  // namespace
}  // namespace icrkit::sim

namespace icrkit::sim {
namespace {
// The SR4000's strong barrel distortion (k1 = -0.82): MRPT's unprojection
// look-up table undistorts each pixel's ray itself, so the raw range image
// unprojects onto the wall; calling CObservation3DRangeScan::undistort()
// first corrects twice.
TEST(Rawlog, MrptUnprojectionUndistortsTheRays) {
  TriangleMesh wall;
  wall.vertices.positions = {{-3, -3, 1}, {3, -3, 1}, {3, 3, 1}, {-3, 3, 1}};
  wall.faces = {{0, 1, 2}, {0, 2, 3}};
  const RayCaster caster(wall);
  SensorModel model = swissRangerSr4000();
  View view;  // optical frame = object frame: the wall at z = 1 m
  std::vector<SimulatedScan> scans{simulateScan(caster, SceneAppearance{}, view.true_camera, model, 1)};
  scans[0].range = scans[0].true_range;  // noise-free
  const fs::path dir = fs::temp_directory_path() / ("icrkit_rawlog_lens_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  writeRawlog((dir / "wall.rawlog").string(), model, scans, {view});
  mrpt::obs::CRawlog rawlog;
  ASSERT_TRUE(rawlog.loadFromRawLogFile((dir / "wall.rawlog").string()));
  for (bool undistort : {false, true}) {
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(rawlog.getAsObservation(0));
    if (undistort) obs->undistort();
    mrpt::maps::CSimplePointsMap points;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    obs->unprojectInto(points, pp);
    double worst = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      float x, y, z;
      points.getPoint(k, x, y, z);
      worst = std::max(worst, caster.closestPoint(Eigen::Vector3d(x, y, z)).distance);
    }
    std::cout << (undistort ? "with" : "without") << " undistort(): worst distance to the wall " << worst * 1e3
              << " mm\n";
    if (undistort)
      EXPECT_GT(worst, 0.02);
    else
      EXPECT_LT(worst, 0.002);  // MRPT's single-precision table, out to the image corners
  }
  fs::remove_all(dir);
}
}  // namespace
}  // namespace icrkit::sim
