// ToF range calibration: the model and the correction on a hand-made scan
// with a known answer, the fit on a simulated SR4000 recording whose
// wiggling error is known, the model file, and bad input.

#include <icrkit/reconstruction/calibration/range_calibration.hpp>

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/sim/range_sensor.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace icrkit::reconstruction {
namespace {

using testing_support::scratchFolder;
using testing_support::simulatedRecording;

TEST(RangeCalibration, ModelAndCorrectionOnAHandMadeScan) {
  RangeErrorModel model;
  model.wavelength = 1.0;
  model.offset = 0.002;
  model.slope = 0.01;
  model.sine = 0.003;
  EXPECT_NEAR(model.error(0.25), 0.002 + 0.0025 + 0.003, 1e-12);  // sin(pi/2) = 1
  EXPECT_FALSE(model.isZero());
  EXPECT_TRUE(RangeErrorModel{}.isZero());

  // Three pixels of a ToF scan: ray lengths 0.25, 0.5 and 0.001 m (the last
  // one's correction would make it negative) along three directions.
  RangeScan scan;
  scan.width = 3;
  scan.height = 1;
  scan.range_is_depth = false;
  scan.sensor_pose.translation() = Eigen::Vector3d(1, 2, 3);
  scan.range = {0.25f, 0.5f, 0.001f};
  const Eigen::Vector3d directions[3] = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.6, 0.8, 0),
                                         Eigen::Vector3d(0, 0, 1)};
  for (std::uint32_t k = 0; k < 3; ++k) {
    scan.points.push_back(scan.sensor_pose.translation() + directions[k] * double(scan.range[k]));
    scan.pixels.push_back(k);
  }
  EXPECT_EQ(correctRange(scan, model), 1u);
  ASSERT_EQ(scan.points.size(), 2u);
  const double r0 = 0.25 - model.error(0.25), r1 = 0.5 - model.error(0.5);
  EXPECT_NEAR(scan.range[0], r0, 1e-6);
  EXPECT_NEAR(scan.range[1], r1, 1e-6);
  EXPECT_EQ(scan.range[2], 0.0f);
  EXPECT_NEAR((scan.points[0] - scan.sensor_pose.translation()).norm(), r0, 1e-6);
  EXPECT_TRUE((scan.points[1] - scan.sensor_pose.translation()).normalized().isApprox(directions[1], 1e-6));
  EXPECT_EQ(correctRange(scan, RangeErrorModel{}), 0u);  // a zero model changes nothing
}

TEST(RangeCalibration, RecoversTheSimulatedSr4000Wiggling) {
  // A reference recording at exact poses: the scene (table and object) is known.
  const std::string dir = simulatedRecording(8, true, sim::SensorType::Sr4000, "paper_cup");
  const TriangleMesh scene = io::readTriangleMesh(dir + "/scene.ply");
  const RangeCalibrationResult r = calibrateRangeError(dir + "/scans.rawlog", {}, scene);
  std::printf("%zu samples over %.2f-%.2f m: rms %.2f -> %.2f mm; offset %.2f mm, slope %.2f mm/m, periodic %.2f mm\n",
              r.report.samples, r.report.min_range_m, r.report.max_range_m, r.report.rms_before_m * 1e3,
              r.report.rms_after_m * 1e3, r.model.offset * 1e3, r.model.slope * 1e3,
              std::hypot(r.model.sine, r.model.cosine) * 1e3);
  EXPECT_GT(r.report.samples, 10000u);
  EXPECT_LT(r.report.rms_after_m, 0.8 * r.report.rms_before_m);
  // Where the samples are (the object and the table around it), the fitted
  // curve is the simulator's wiggling term.
  const sim::SensorModel sensor = sim::swissRangerSr4000();
  for (double range = 0.4; range <= 0.9; range += 0.05) {
    const double truth = sensor.wiggling_amplitude * std::sin(2 * M_PI * range / sensor.wiggling_wavelength);
    EXPECT_NEAR(r.model.error(range), truth, 0.0006) << "at " << range << " m";
  }
}

TEST(RangeCalibration, ModelFileRoundTripAndBadInput) {
  const std::filesystem::path scratch = scratchFolder("range_model");
  RangeErrorModel model;
  model.wavelength = 1.249;
  model.offset = -0.001;
  model.slope = 0.002;
  model.sine = 0.004;
  model.cosine = -0.0005;
  const std::string path = (scratch / "model.json").string();
  writeRangeErrorModel(path, model, {});
  const RangeErrorModel back = readRangeErrorModel(path);
  EXPECT_EQ(back.wavelength, model.wavelength);
  EXPECT_EQ(back.offset, model.offset);
  EXPECT_EQ(back.slope, model.slope);
  EXPECT_EQ(back.sine, model.sine);
  EXPECT_EQ(back.cosine, model.cosine);

  EXPECT_THROW(readRangeErrorModel((scratch / "missing.json").string()), InputError);
  std::ofstream((scratch / "other.json").string()) << "{\"format\": \"something else\"}";
  EXPECT_THROW(readRangeErrorModel((scratch / "other.json").string()), InputError);
  std::ofstream((scratch / "broken.json").string()) << "{\"format\": \"icrkit range error model 1\", \"offset_m\": \"x\"}";
  try {
    readRangeErrorModel((scratch / "broken.json").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos) << e.what();
  }

  // A scene the recording does not show: nothing to fit.
  const std::string dir = simulatedRecording(3, true, sim::SensorType::Sr4000, "paper_cup");
  TriangleMesh far_away;
  far_away.vertices.positions = {Eigen::Vector3d(50, 0, 0), Eigen::Vector3d(50, 1, 0), Eigen::Vector3d(50, 0, 1)};
  far_away.faces = {{0, 1, 2}};
  EXPECT_THROW(calibrateRangeError(dir + "/scans.rawlog", {}, far_away), InputError);
  EXPECT_THROW(calibrateRangeError(dir + "/scans.rawlog", {}, TriangleMesh{}), InputError);
  std::filesystem::remove_all(scratch);
}

}  // namespace
}  // namespace icrkit::reconstruction
