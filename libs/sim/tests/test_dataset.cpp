#include <icrkit/sim/cad_objects.hpp>
#include <icrkit/sim/dataset.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/pose_mrpt.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace icrkit::sim {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("icrkit_dataset_" + name + "_" + std::to_string(::getpid()));
}

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}


// Unprojects every view with MRPT, placed with the ground-truth pose, and
// measures how far the object's points are from the CAD surface.
struct SurfaceErrors {
  std::vector<double> distances;
  std::size_t points = 0;
};
SurfaceErrors unprojectWithTruth(const fs::path& dir) {
  const TriangleMesh object = io::readTriangleMesh((dir / "object.ply").string());
  const RayCaster caster(object);
  const std::vector<StampedPose> truth = readTumTrajectory((dir / "ground_truth.txt").string());
  mrpt::obs::CRawlog rawlog;
  EXPECT_TRUE(rawlog.loadFromRawLogFile((dir / "scans.rawlog").string()));
  EXPECT_EQ(rawlog.size(), truth.size());
  SurfaceErrors errors;
  const Eigen::Vector3d lo = object.vertices.bounds().min(), hi = object.vertices.bounds().max();
  for (std::size_t i = 0; i < rawlog.size(); ++i) {
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(rawlog.getAsObservation(i));
    if (!obs) continue;
    obs->sensorPose = toCPose3D(truth[i].pose);
    mrpt::maps::CSimplePointsMap points;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    obs->unprojectInto(points, pp);
    for (std::size_t k = 0; k < points.size(); ++k) {
      float x, y, z;
      points.getPoint(k, x, y, z);
      const Eigen::Vector3d p(x, y, z);
      ++errors.points;
      // Object points only: inside its box grown by 1 cm and above the
      // fixtures (which stop just below z = 0).
      if ((p.array() < lo.array() - 0.01).any() || (p.array() > hi.array() + 0.01).any() || p.z() < 0.003) continue;
      errors.distances.push_back(caster.closestPoint(p).distance);
    }
  }
  std::sort(errors.distances.begin(), errors.distances.end());
  return errors;
}

double quantile(const std::vector<double>& sorted, double q) {
  return sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

class SimulatedRecording : public ::testing::TestWithParam<SensorType> {};

TEST_P(SimulatedRecording, UnprojectsOntoTheCadMeshWithinTheNoise) {
  DatasetSpec spec;
  spec.object = "cup";
  spec.sensor = GetParam();
  spec.acquisition.setup = spec.sensor == SensorType::Kinect ? sim::Setup::B : sim::Setup::A;
  spec.acquisition.views = 4;
  const fs::path dir = scratch(sensorTypeName(spec.sensor));
  const SimulationReport summary = simulateDataset(spec, dir.string());
  EXPECT_EQ(summary.views, 4u);
  EXPECT_GT(summary.object_pixel_fraction, 0.01);
  for (const char* f : {"scans.rawlog", "ground_truth.txt", "reported_poses.txt", "object.ply", "scene.ply", "manifest.json"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const SurfaceErrors e = unprojectWithTruth(dir);
  ASSERT_GT(e.distances.size(), 1000u);
  // Kinect at 0.7 m: axial sigma about 1.5 mm, depth steps of about 1.5 mm;
  // SR4000 at 0.6 m: a few mm of noise plus up to 5 mm of wiggling. Mixed
  // pixels at the silhouette make the far tail.
  const double median = quantile(e.distances, 0.5), q90 = quantile(e.distances, 0.9);
  std::cout << sensorTypeName(spec.sensor) << ": " << e.distances.size() << " object points, distance to the CAD "
            << "surface median " << median * 1e3 << " mm, 90 % " << q90 * 1e3 << " mm\n";
  EXPECT_LT(median, 0.004);
  EXPECT_LT(q90, 0.012);
  const nlohmann::json manifest = nlohmann::json::parse(readBytes(dir / "manifest.json"));
  EXPECT_EQ(manifest["views"], 4);
  EXPECT_EQ(manifest["sensor"]["type"], sensorTypeName(spec.sensor));
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(BothSensors, SimulatedRecording, ::testing::Values(SensorType::Kinect, SensorType::Sr4000));

// Every one of the paper's nine recordings (two views each here) reads back
// onto its CAD mesh.
TEST(Dataset, EveryPaperRecordingUnprojectsOntoItsMesh) {
  for (DatasetSpec spec : paperDatasets()) {
    spec.acquisition.views = 2;
    const fs::path dir = scratch(datasetName(spec));
    simulateDataset(spec, dir.string());
    const SurfaceErrors e = unprojectWithTruth(dir);
    EXPECT_GT(e.distances.size(), 500u) << datasetName(spec);
    EXPECT_LT(quantile(e.distances, 0.5), 0.004) << datasetName(spec);
    EXPECT_LT(quantile(e.distances, 0.9), 0.012) << datasetName(spec);
    fs::remove_all(dir);
  }
}

TEST(Dataset, SameSeedSameBytes) {
  DatasetSpec spec;
  spec.object = "wooden_toy_1";
  spec.sensor = SensorType::Sr4000;
  spec.acquisition.setup = sim::Setup::A;
  spec.acquisition.views = 3;
  const fs::path a = scratch("a"), b = scratch("b");
  simulateDataset(spec, a.string());
  simulateDataset(spec, b.string());
  EXPECT_EQ(readBytes(a / "scans.rawlog"), readBytes(b / "scans.rawlog"));
  EXPECT_EQ(readBytes(a / "ground_truth.txt"), readBytes(b / "ground_truth.txt"));
  spec.acquisition.seed = 2;
  simulateDataset(spec, b.string());  // replaces the earlier simulation
  EXPECT_NE(readBytes(a / "scans.rawlog"), readBytes(b / "scans.rawlog"));
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(Dataset, BadInputLeavesNothingBehind) {
  DatasetSpec spec;
  spec.acquisition.views = 2;
  const fs::path dir = scratch("bad");
  spec.object = "teapot";
  EXPECT_THROW(simulateDataset(spec, dir.string()), InputError);
  spec.object = "cup";
  spec.acquisition.views = 0;
  EXPECT_THROW(simulateDataset(spec, dir.string()), InputError);
  spec.acquisition.views = 2;
  spec.mesh_path = (dir / "missing.ply").string();
  EXPECT_THROW(simulateDataset(spec, dir.string()), InputError);
  EXPECT_FALSE(fs::exists(dir));
  // A folder with someone else's files is not replaced.
  fs::create_directories(dir);
  std::ofstream(dir / "notes.txt") << "mine";
  spec.mesh_path.clear();
  EXPECT_THROW(simulateDataset(spec, dir.string()), InputError);
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  fs::remove_all(dir);
  // An unwritable place.
  EXPECT_THROW(simulateDataset(spec, "/proc/icrkit_cannot_write_here"), InputError);
}

TEST(Dataset, PaperListMatchesTheDatasetsFile) {
  const std::vector<DatasetSpec> specs = paperDatasets();
  ASSERT_EQ(specs.size(), 9u);
  std::ifstream in(std::string(ICRKIT_SOURCE_DIR) + "/datasets/paper_datasets.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json file = nlohmann::json::parse(in);
  ASSERT_EQ(file["datasets"].size(), specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const nlohmann::json& d = file["datasets"][i];
    EXPECT_EQ(d["name"], datasetName(specs[i]));
    EXPECT_EQ(d["object"], specs[i].object);
    EXPECT_EQ(d["sensor"], sensorTypeName(specs[i].sensor));
    EXPECT_EQ(d["setup"], setupName(specs[i].acquisition.setup));
    EXPECT_EQ(d["views"], specs[i].acquisition.views);
    EXPECT_EQ(d["seed"], specs[i].acquisition.seed);
  }
}

}  // namespace
}  // namespace icrkit::sim
