/// \file
/// Rawlog reading: simulated recordings read back against MRPT's own
/// CRawlog + unprojectInto, the TUM override, both layouts, external
/// images, and the bad inputs the reader must name.

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/pose_mrpt.hpp>
#include <icrkit/core/ray_caster.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/sim/rawlog_writer.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;
using testing_support::scratchFolder;
using testing_support::simulatedRecording;

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> loadWithMrpt(const std::string& path) {
  mrpt::obs::CRawlog rawlog;
  EXPECT_TRUE(rawlog.loadFromRawLogFile(path));
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> out;
  for (std::size_t i = 0; i < rawlog.size(); ++i)
    if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(rawlog.getAsObservation(i)))
      out.push_back(o);
  return out;
}

using test::expectInputError;

TEST(RawlogReader, MatchesMrptUnprojection) {
  const std::string dir = simulatedRecording(4, false);
  const std::string path = dir + "/scans.rawlog";
  const auto reference = loadWithMrpt(path);
  ASSERT_EQ(reference.size(), 4u);
  const auto reported = readTumTrajectory(dir + "/reported_poses.txt");

  RawlogReader reader(path);
  std::size_t count = 0;
  while (auto scan = reader.next()) {
    ASSERT_LT(count, reference.size());
    auto& obs = *reference[count];
    EXPECT_EQ(scan->index, count);
    EXPECT_EQ(scan->sensor_label, "KINECT");
    EXPECT_TRUE(scan->range_is_depth);
    EXPECT_EQ(scan->width, 640);
    EXPECT_EQ(scan->height, 480);
    EXPECT_NEAR(scan->timestamp, mrpt::Clock::toDouble(obs.timestamp), 1e-6);
    EXPECT_GT(scan->timestamp, sim::kRawlogEpoch - 1);
    EXPECT_TRUE(scan->sensor_pose.isApprox(reported[count].pose, 1e-9));
    EXPECT_FALSE(scan->intensity.empty());
    EXPECT_EQ(scan->intensity.channels, 3);
    EXPECT_FALSE(scan->intensity_is_ir);
    EXPECT_EQ(scan->confidence.width, 640);

    mrpt::maps::CSimplePointsMap cloud;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    obs.unprojectInto(cloud, pp);
    EXPECT_EQ(scan->points.size(), scan->validPixels());
    ASSERT_EQ(scan->points.size(), cloud.size());
    const Eigen::Isometry3d to_sensor = scan->sensor_pose.inverse();
    const Eigen::Matrix3d axes = mrptSensorAxesInOptical();
    double worst_pixel = 0;
    for (std::size_t k = 0; k < cloud.size(); ++k) {
      float x, y, z;
      cloud.getPoint(k, x, y, z);
      ASSERT_EQ(scan->points[k], Eigen::Vector3d(x, y, z));
      // The reported pixel is where the point projects (MRPT unprojects
      // without distortion, so the pinhole model inverts it).
      const Eigen::Vector3d optical = axes * (to_sensor * scan->points[k]);
      const double u = scan->camera.fx * optical.x() / optical.z() + scan->camera.cx;
      const double v = scan->camera.fy * optical.y() / optical.z() + scan->camera.cy;
      const int col = static_cast<int>(scan->pixels[k] % scan->width);
      const int row = static_cast<int>(scan->pixels[k] / scan->width);
      worst_pixel = std::max({worst_pixel, std::abs(u - col), std::abs(v - row)});
      EXPECT_NEAR(optical.z(), scan->range[scan->pixels[k]], 2e-4);
    }
    EXPECT_LT(worst_pixel, 0.01);
    ++count;
  }
  EXPECT_EQ(count, 4u);
  EXPECT_EQ(reader.scansRead(), 4u);
}

TEST(RawlogReader, PerfectPosesPutPointsOnTheScene) {
  const std::string dir = simulatedRecording(4, true);
  const RayCaster scene(io::readTriangleMesh(dir + "/scene.ply"));
  const auto scans = readAllScans(dir + "/scans.rawlog");
  ASSERT_EQ(scans.size(), 4u);
  for (const RangeScan& scan : scans) {
    ASSERT_GT(scan.points.size(), 1000u);
    std::vector<double> d;
    for (std::size_t k = 0; k < scan.points.size(); k += 7) d.push_back(scene.closestPoint(scan.points[k]).distance);
    std::sort(d.begin(), d.end());
    // Kinect noise and quantisation, not pose errors.
    EXPECT_LT(d[d.size() / 2], 0.003) << "scan " << scan.index;
  }
}

TEST(RawlogReader, TumFileOverridesSensorPoses) {
  const std::string dir = simulatedRecording(4, false);
  const auto truth = readTumTrajectory(dir + "/ground_truth.txt");
  const auto rawlog_scans = readAllScans(dir + "/scans.rawlog");
  RawlogReaderOptions options;
  options.pose_file = dir + "/ground_truth.txt";
  const auto scans = readAllScans(dir + "/scans.rawlog", options);
  ASSERT_EQ(scans.size(), rawlog_scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    EXPECT_TRUE(scans[i].sensor_pose.isApprox(truth[i].pose, 1e-12));
    const Eigen::Isometry3d change = truth[i].pose * rawlog_scans[i].sensor_pose.inverse();
    ASSERT_EQ(scans[i].points.size(), rawlog_scans[i].points.size());
    double worst = 0;
    for (std::size_t k = 0; k < scans[i].points.size(); ++k)
      worst = std::max(worst, (scans[i].points[k] - change * rawlog_scans[i].points[k]).norm());
    EXPECT_LT(worst, 1e-5);  // MRPT's single precision
  }
}

TEST(RawlogReader, TooFewPosesNameTheScan) {
  const std::string dir = simulatedRecording(4, false);
  const fs::path scratch = scratchFolder("few_poses");
  const auto truth = readTumTrajectory(dir + "/ground_truth.txt");
  writeTumTrajectory((scratch / "two.txt").string(), {truth[0], truth[1]});
  RawlogReaderOptions options;
  options.pose_file = (scratch / "two.txt").string();
  const InputError e = expectInputError([&] { readAllScans(dir + "/scans.rawlog", options); });
  EXPECT_EQ(e.location(), "scan 2");
  EXPECT_EQ(e.source(), options.pose_file);
  fs::remove_all(scratch);
}

TEST(RawlogReader, TruncatedGzipNamesTheScanReached) {
  const std::string dir = simulatedRecording(4, false);
  const fs::path scratch = scratchFolder("truncated");
  std::ifstream in(dir + "/scans.rawlog", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string path = (scratch / "half.rawlog").string();
  std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::size_t complete = 0;
  const InputError e = expectInputError([&] {
    RawlogReader reader(path);
    while (reader.next()) ++complete;
  });
  EXPECT_EQ(e.source(), path);
  EXPECT_LT(complete, 4u);
  EXPECT_EQ(e.location(), "scan " + std::to_string(complete));
  fs::remove_all(scratch);
}

// The observations written as a plain (uncompressed) rawlog at `path`; its bytes.
std::string plainRawlogBytes(const std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& observations,
                             const std::string& path) {
  {
    mrpt::io::CFileOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    for (const auto& obs : observations) archive << *obs;
  }
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(RawlogReader, TruncatedPlainFileNamesTheScanReached) {
  const std::string dir = simulatedRecording(4, false);
  const fs::path scratch = scratchFolder("truncated_plain");
  const auto reference = loadWithMrpt(dir + "/scans.rawlog");
  const std::string bytes = plainRawlogBytes(reference, (scratch / "whole.rawlog").string());
  const std::string path = (scratch / "cut.rawlog").string();
  // Cut inside the third scan.
  std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() * 5 / 8);
  std::size_t complete = 0;
  const InputError e = expectInputError([&] {
    RawlogReader reader(path);
    while (reader.next()) ++complete;
  });
  EXPECT_EQ(complete, 2u);
  EXPECT_EQ(e.location(), "scan 2");
  fs::remove_all(scratch);
}

// `v` as MRPT writes a uint32 (little endian).
std::string littleEndianWord(std::uint32_t v) {
  std::string w;
  for (int k = 0; k < 4; ++k) w.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
  return w;
}

// Writes `bytes` (a rawlog corrupted in its second scan) into `scratch`:
// the reader gives the first scan, then an InputError saying `refusal`.
void expectRefusedAfterOneScan(const std::string& bytes, const fs::path& scratch, const std::string& refusal) {
  const std::string path = (scratch / "absurd.rawlog").string();
  std::ofstream(path, std::ios::binary) << bytes;
  std::size_t complete = 0;
  const InputError e = expectInputError([&] {
    RawlogReader reader(path);
    while (reader.next()) ++complete;
  });
  EXPECT_EQ(complete, 1u);
  EXPECT_NE(std::string(e.what()).find(refusal), std::string::npos) << e.what();
  fs::remove_all(scratch);
}

TEST(RawlogReader, AbsurdRangeImageSizeIsRefusedBeforeMrptAllocatesIt) {
  // MRPT allocates rows x cols as soon as it has read them; for a corrupt
  // size its allocator returns null and it writes through it (a crash the
  // rawlog fuzz target found). The reader refuses the size first.
  const std::string dir = simulatedRecording(3, false);
  const fs::path scratch = scratchFolder("absurd_size");
  const auto reference = loadWithMrpt(dir + "/scans.rawlog");
  std::string bytes = plainRawlogBytes(reference, (scratch / "whole.rawlog").string());
  // The second scan's range image sizes: after its has-range flag (1) and
  // range units (float), rows and cols as little-endian words.
  const auto& second = *reference[1];
  const std::uint32_t rows = static_cast<std::uint32_t>(second.rangeImage.rows());
  const std::uint32_t cols = static_cast<std::uint32_t>(second.rangeImage.cols());
  std::string pattern(1, '\x01');
  pattern.append(reinterpret_cast<const char*>(&second.rangeUnits), sizeof(float));
  pattern += littleEndianWord(rows) + littleEndianWord(cols);
  const std::size_t first = bytes.find(pattern);
  ASSERT_NE(first, std::string::npos);
  const std::size_t found = bytes.find(pattern, first + 1);
  ASSERT_NE(found, std::string::npos);
  const std::size_t at = found + 5;
  const std::string huge = "\x12\x34\x56\xF0\x01\x00\x00\x80";
  bytes.replace(at, 8, huge);
  expectRefusedAfterOneScan(bytes, scratch, "a range image of");
}

TEST(RawlogReader, AbsurdCameraNameLengthIsRefusedBeforeMrptAllocatesIt) {
  // A camera's intrinsics end with its name; MRPT sizes the string from its
  // stored length before reading it. The rawlog fuzz target found a 2 MB
  // file whose corrupt length asked for 3.6 GB. The reader refuses it.
  const std::string dir = simulatedRecording(3, false);
  const fs::path scratch = scratchFolder("absurd_name");
  const auto reference = loadWithMrpt(dir + "/scans.rawlog");
  std::string bytes = plainRawlogBytes(reference, (scratch / "whole.rawlog").string());
  const std::string& name = reference[1]->cameraParams.cameraName;
  ASSERT_FALSE(name.empty());
  const std::string pattern = littleEndianWord(static_cast<std::uint32_t>(name.size())) + name;
  // The first scan's two cameras (depth, intensity), then the second's.
  std::size_t at = std::string::npos;
  for (int occurrence = 0, from = 0; occurrence < 3; ++occurrence) {
    at = bytes.find(pattern, static_cast<std::size_t>(from));
    ASSERT_NE(at, std::string::npos) << occurrence;
    from = static_cast<int>(at + 1);
  }
  bytes.replace(at, 4, std::string("\x08\x02\x01\xD9", 4));
  expectRefusedAfterOneScan(bytes, scratch, "a camera name of");
}

TEST(RawlogReader, AbsurdSensorLabelLengthIsRefusedBeforeMrptAllocatesIt) {
  // A range scan's tail (after its intensity camera) holds strings MRPT
  // sizes from their stored length before reading them, the sensor label
  // first: a corrupt length is refused as the camera name's is.
  const std::string dir = simulatedRecording(3, false);
  const fs::path scratch = scratchFolder("absurd_label");
  const auto reference = loadWithMrpt(dir + "/scans.rawlog");
  std::string bytes = plainRawlogBytes(reference, (scratch / "whole.rawlog").string());
  const std::string& label = reference[1]->sensorLabel;
  ASSERT_FALSE(label.empty());
  const std::string pattern = littleEndianWord(static_cast<std::uint32_t>(label.size())) + label;
  const std::size_t first = bytes.find(pattern);
  ASSERT_NE(first, std::string::npos);
  const std::size_t second = bytes.find(pattern, first + 1);
  ASSERT_NE(second, std::string::npos);
  bytes.replace(second, 4, std::string("\x00\x00\x00\xF0", 4));
  expectRefusedAfterOneScan(bytes, scratch, "a sensor label of 4026531840 bytes");
}

TEST(RawlogReader, MissingAndEmptyFiles) {
  const fs::path scratch = scratchFolder("missing");
  const std::string missing = (scratch / "nope.rawlog").string();
  EXPECT_EQ(expectInputError([&] { RawlogReader reader(missing); }).source(), missing);
  const std::string empty = (scratch / "empty.rawlog").string();
  std::ofstream(empty).close();
  const InputError e = expectInputError([&] { RawlogReader reader(empty); });
  EXPECT_NE(e.detail().find("no 3D range scans"), std::string::npos) << e.what();
  fs::remove_all(scratch);
}

TEST(RawlogReader, NoThreeDScans) {
  const fs::path scratch = scratchFolder("no3d");
  const std::string path = (scratch / "laser.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    mrpt::obs::CObservation2DRangeScan laser;
    laser.resizeScan(10);
    archive << laser << laser;
  }
  const InputError e = expectInputError([&] { RawlogReader reader(path); });
  EXPECT_NE(e.detail().find("no 3D range scans"), std::string::npos) << e.what();
  fs::remove_all(scratch);
}

mrpt::obs::CObservation3DRangeScan smallScan(int w, int h) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.cameraParams.ncols = w;
  obs.cameraParams.nrows = h;
  obs.cameraParams.setIntrinsicParamsFromValues(50, 50, (w - 1) / 2.0, (h - 1) / 2.0);
  obs.cameraParamsIntensity = obs.cameraParams;
  obs.hasRangeImage = true;
  obs.rangeUnits = 0.001f;
  obs.rangeImage_setSize(h, w);
  obs.rangeImage.fill(1000);
  obs.maxRange = 5;
  return obs;
}

// A sensorPose whose stored matrix is a rotation disturbed by `amount` per
// entry (MRPT keeps and serialises the 3x3 matrix as given).
mrpt::poses::CPose3D disturbedSensorPose(double amount) {
  Eigen::Isometry3d pose =
      Eigen::Translation3d(0.05, -0.6, 0.3) * Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.2, 0.5, -1.0).normalized());
  Eigen::Matrix3d noise;
  noise << 0.4, -0.9, 0.2,  //
      -0.3, 0.7, 1.0,       //
      0.8, -0.1, -0.6;
  pose.linear() += amount * noise;
  mrpt::math::CMatrixDouble44 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = pose.matrix()(r, c);
  return mrpt::poses::CPose3D(m);
}

TEST(RawlogReader, NearlyOrthonormalPoseIsProjectedAndCounted) {
  const fs::path scratch = scratchFolder("rotation_inside");
  const std::string path = (scratch / "x.rawlog").string();
  const mrpt::poses::CPose3D disturbed = disturbedSensorPose(5e-6);
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    auto exact = smallScan(8, 6);
    exact.sensorPose = mrpt::poses::CPose3D(0.1, 0.2, 0.3, 0.4, -0.5, 0.6);
    auto rounded = smallScan(8, 6);
    rounded.sensorPose = disturbed;
    archive << exact << rounded;
  }
  const Eigen::Matrix3d stored = toIsometry(disturbed).linear();
  ASSERT_GT(orthonormalityError(stored), 1e-6);  // what a 7-digit pose log leaves
  ASSERT_LT(orthonormalityError(stored), kReadRotationTolerance);
  const auto scans = readAllScans(path);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_FALSE(scans[0].pose_orthonormalised);
  EXPECT_TRUE(scans[1].pose_orthonormalised);
  const Eigen::Isometry3d& pose = scans[1].sensor_pose;
  EXPECT_LE(orthonormalityError(pose.linear()), 1e-12);
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  EXPECT_LT((pose.linear() - stored).cwiseAbs().maxCoeff(), 2e-5);
  // MRPT unprojected with the repaired pose: every point is the pose times
  // its optical ray (depth 1 m), in single precision.
  ASSERT_EQ(scans[1].points.size(), 48u);
  for (std::size_t k = 0; k < scans[1].points.size(); ++k) {
    const int row = static_cast<int>(scans[1].pixels[k]) / 8, col = static_cast<int>(scans[1].pixels[k]) % 8;
    const Eigen::Vector3d optical = opticalPoint(scans[1], row, col, 1.0);
    const Eigen::Vector3d expected = pose * (mrptSensorAxesInOptical().transpose() * optical);
    EXPECT_LT((scans[1].points[k] - expected).norm(), 1e-6) << k;
  }
  fs::remove_all(scratch);
}

TEST(RawlogReader, PoseFarFromARotationNamesTheScan) {
  const fs::path scratch = scratchFolder("rotation_outside");
  const std::string path = (scratch / "x.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    auto exact = smallScan(8, 6);
    auto scaled = smallScan(8, 6);
    scaled.sensorPose = disturbedSensorPose(0.03);
    archive << exact << scaled;
  }
  RawlogReader reader(path);
  EXPECT_TRUE(reader.next());
  const InputError e = expectInputError([&] { reader.next(); });
  EXPECT_EQ(e.source(), path);
  EXPECT_EQ(e.location(), "scan 1");
  EXPECT_NE(e.detail().find("not orthonormal"), std::string::npos) << e.what();

  // A looser tolerance accepts it (and projects it).
  RawlogReaderOptions loose;
  loose.rotation_tolerance = 0.1;
  const auto scans = readAllScans(path, loose);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_TRUE(scans[1].pose_orthonormalised);
  EXPECT_LE(orthonormalityError(scans[1].sensor_pose.linear()), 1e-12);

  // A pose file replaces the recorded pose, which is then not checked.
  const std::string poses = (scratch / "poses.txt").string();
  { std::ofstream(poses) << "0 0 0 0 0 0 0 1\n1 0 0 1 0 0 0.7071067811865476 0.7071067811865476\n"; }
  RawlogReaderOptions replaced;
  replaced.pose_file = poses;
  const auto replaced_scans = readAllScans(path, replaced);
  ASSERT_EQ(replaced_scans.size(), 2u);
  EXPECT_FALSE(replaced_scans[1].pose_orthonormalised);
  EXPECT_EQ(replaced_scans[1].sensor_pose.translation(), Eigen::Vector3d(0, 0, 1));
  fs::remove_all(scratch);
}

TEST(RawlogReader, PoseFileQuaternionOffUnitLengthIsNormalisedAndCounted) {
  const fs::path scratch = scratchFolder("quaternion");
  const std::string path = (scratch / "x.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << smallScan(8, 6) << smallScan(8, 6);
  }
  const std::string poses = (scratch / "poses.txt").string();
  {
    std::ofstream out(poses);
    out.precision(17);
    const double c = 0.9999 * std::sqrt(0.5);
    out << "0 0 0 0 0 0 0 1\n1 0 0 1 0 0 " << c << " " << c << "\n";
  }
  RawlogReaderOptions options;
  options.pose_file = poses;
  const auto scans = readAllScans(path, options);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_FALSE(scans[0].pose_orthonormalised);
  EXPECT_TRUE(scans[1].pose_orthonormalised);
  EXPECT_LE(orthonormalityError(scans[1].sensor_pose.linear()), 1e-12);
  fs::remove_all(scratch);
}

TEST(RawlogReader, ScanWithoutRangeImage) {
  const fs::path scratch = scratchFolder("norange");
  const std::string path = (scratch / "x.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    mrpt::obs::CObservation3DRangeScan good = smallScan(8, 6), bad;
    archive << good << bad;
  }
  const InputError e = expectInputError([&] { readAllScans(path); });
  EXPECT_EQ(e.location(), "scan 1");
  EXPECT_NE(e.detail().find("no range image"), std::string::npos) << e.what();
  fs::remove_all(scratch);
}

TEST(RawlogReader, InconsistentImageSizes) {
  const fs::path scratch = scratchFolder("sizes");
  const std::string path = (scratch / "x.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    auto good = smallScan(8, 6);
    auto bad_confidence = smallScan(8, 6);
    bad_confidence.hasConfidenceImage = true;
    bad_confidence.confidenceImage = mrpt::img::CImage(7, 6, mrpt::img::CH_GRAY);
    archive << good << bad_confidence;
  }
  RawlogReader reader(path);
  EXPECT_TRUE(reader.next());
  InputError e = expectInputError([&] { reader.next(); });
  EXPECT_EQ(e.location(), "scan 1");
  EXPECT_NE(e.detail().find("confidence image"), std::string::npos) << e.what();

  // (MRPT itself fixes a cameraParams size that disagrees with the range
  // image when it reads the observation, so that case cannot be written.)
  const fs::path path2 = scratch / "y.rawlog";
  {
    mrpt::io::CFileGZOutputStream out(path2.string());
    auto archive = mrpt::serialization::archiveFrom(out);
    auto bad_intensity = smallScan(8, 6);
    bad_intensity.hasIntensityImage = true;
    bad_intensity.intensityImage = mrpt::img::CImage(4, 3, mrpt::img::CH_GRAY);
    archive << bad_intensity;
  }
  RawlogReader reader2(path2.string());
  e = expectInputError([&] { reader2.next(); });
  EXPECT_EQ(e.location(), "scan 0");
  EXPECT_NE(e.detail().find("intensity image"), std::string::npos) << e.what();
  fs::remove_all(scratch);
}

TEST(RawlogReader, SensoryFrameLayoutPlainFile) {
  const std::string dir = simulatedRecording(4, false);
  const auto reference = loadWithMrpt(dir + "/scans.rawlog");
  const fs::path scratch = scratchFolder("frames");
  const std::string path = (scratch / "frames.rawlog").string();
  {
    mrpt::io::CFileOutputStream out(path);  // plain, not gzip
    auto archive = mrpt::serialization::archiveFrom(out);
    for (std::size_t i = 0; i < reference.size(); i += 2) {
      mrpt::obs::CActionCollection actions;
      mrpt::obs::CSensoryFrame frame;
      frame.insert(reference[i]);
      auto laser = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
      laser->resizeScan(4);
      frame.insert(laser);  // skipped by the reader
      if (i + 1 < reference.size()) frame.insert(reference[i + 1]);
      archive << actions << frame;
    }
  }
  const auto direct = readAllScans(dir + "/scans.rawlog");
  const auto framed = readAllScans(path);
  ASSERT_EQ(framed.size(), direct.size());
  for (std::size_t i = 0; i < direct.size(); ++i) {
    EXPECT_EQ(framed[i].index, i);
    EXPECT_EQ(framed[i].points, direct[i].points);
    EXPECT_EQ(framed[i].pixels, direct[i].pixels);
    EXPECT_TRUE(framed[i].sensor_pose.isApprox(direct[i].sensor_pose));
  }
  fs::remove_all(scratch);
}

TEST(RawlogReader, ExternalImagesFromTheImagesFolder) {
  const fs::path scratch = scratchFolder("external");
  fs::create_directories(scratch / "rec_Images");
  const std::string path = (scratch / "rec.rawlog").string();
  mrpt::img::CImage amplitude(8, 6, mrpt::img::CH_GRAY);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 8; ++c) *amplitude.ptr<std::uint8_t>(c, r) = static_cast<std::uint8_t>(10 * r + c);
  ASSERT_TRUE(amplitude.saveToFile((scratch / "rec_Images" / "amp_0.png").string()));
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto archive = mrpt::serialization::archiveFrom(out);
    auto obs = smallScan(8, 6);
    obs.hasIntensityImage = true;
    obs.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_IR;
    obs.intensityImage.setExternalStorage("amp_0.png");
    archive << obs;
  }
  const auto scans = readAllScans(path);
  ASSERT_EQ(scans.size(), 1u);
  ASSERT_EQ(scans[0].intensity.width, 8);
  ASSERT_EQ(scans[0].intensity.channels, 1);
  EXPECT_TRUE(scans[0].intensity_is_ir);
  EXPECT_EQ(scans[0].intensity.data[5 * 8 + 7], 57);
  EXPECT_EQ(scans[0].points.size(), 48u);
  fs::remove_all(scratch);
}

TEST(RawlogReader, MrptSampleRgbdRawlog) {
  std::vector<fs::path> found;
  for (const char* root : {"/usr/share/mrpt", "/usr/share/mrpt-common", "/usr/share/doc/mrpt-common"}) {
    std::error_code error;
    if (!fs::is_directory(root, error)) continue;
    for (auto it = fs::recursive_directory_iterator(root, error); it != fs::recursive_directory_iterator();
         it.increment(error))
      if (it->path().filename() == "tests_rgbd.rawlog") found.push_back(it->path());
  }
  if (found.empty()) GTEST_SKIP() << "tests_rgbd.rawlog not installed (Debian package mrpt-common absent)";
  RawlogReader reader(found.front().string());
  std::size_t n = 0;
  while (auto scan = reader.next()) {
    EXPECT_EQ(scan->points.size(), scan->validPixels());
    ++n;
  }
  EXPECT_GT(n, 0u);
}

TEST(RawlogReader, ExtraRangeLayersAreFollowedAndAnAbsurdLayerSizeIsRefused) {
  // Version 10 scans may end with extra range layers (a name, the sizes,
  // the pixels), which MRPT allocates from their stored sizes: a file with
  // layers reads whole, and a corrupt layer size is refused.
  const fs::path scratch = scratchFolder("layers");
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> scans;
  for (int k = 0; k < 2; ++k) {
    auto obs = std::make_shared<mrpt::obs::CObservation3DRangeScan>(smallScan(8, 6));
    obs->sensorLabel = "LAYERED";
    mrpt::math::CMatrix_u16 layer(6, 8);
    layer.fill(900);
    obs->rangeImageOtherLayers["strongest"] = layer;
    scans.push_back(obs);
  }
  const std::string whole = (scratch / "whole.rawlog").string();
  std::string bytes = plainRawlogBytes(scans, whole);
  EXPECT_EQ(readAllScans(whole).size(), 2u);
  // MRPT writes a layer's name, then its columns and rows.
  const std::string pattern =
      littleEndianWord(9) + "strongest" + littleEndianWord(8) + littleEndianWord(6);
  const std::size_t first = bytes.find(pattern);
  ASSERT_NE(first, std::string::npos);
  const std::size_t second = bytes.find(pattern, first + 1);
  ASSERT_NE(second, std::string::npos);
  bytes.replace(second + 4 + 9, 8, littleEndianWord(1u << 20) + littleEndianWord(1u << 20));
  expectRefusedAfterOneScan(bytes, scratch, "a range layer of 1048576 x 1048576 elements");
}

}  // namespace
}  // namespace icrkit::reconstruction
