/// \file
/// TUM RGB-D folders: known answers on small synthetic folders written with
/// OpenCV, the bad inputs the reader must name, the real bunny folder
/// against the same recording as a rawlog, and the scan source that opens
/// either.

#include "simulated_recordings.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;
using testing_support::scratchFolder;
using testing_support::simulatedRecording;

std::string sharedData(const std::string& relative) {
  return std::string(ICRKIT_SHARED_DATA_DIR) + "/" + relative;
}

using test::expectInputError;

constexpr int kWidth = 8, kHeight = 6;

// Depth counts of frame f at (row, col): a slanted plane, with one hole.
std::uint16_t counts(int frame, int row, int col) {
  if (row == 2 && col == 3) return 0;
  return static_cast<std::uint16_t>(1000 + 100 * frame + 10 * row + col);
}

// A folder of `frames` 16-bit PNGs listed in depth.txt at t = 10 + f.
fs::path makeFolder(const std::string& name, int frames) {
  const fs::path dir = scratchFolder(name);
  fs::create_directories(dir / "depth");
  std::ofstream list(dir / "depth.txt");
  list << "# depth maps\n# timestamp filename\n";
  for (int f = 0; f < frames; ++f) {
    cv::Mat image(kHeight, kWidth, CV_16UC1);
    for (int r = 0; r < kHeight; ++r)
      for (int c = 0; c < kWidth; ++c) image.at<std::uint16_t>(r, c) = counts(f, r, c);
    const std::string file = "depth/" + std::to_string(10 + f) + ".500000.png";
    EXPECT_TRUE(cv::imwrite((dir / file).string(), image));
    list << 10 + f << ".500000 " << file << "\n";
  }
  return dir;
}

TumFolderOptions withCamera(double depth_scale = 1000.0) {
  TumFolderOptions options;
  CameraIntrinsics k;
  k.fx = 50.0;
  k.fy = 40.0;
  k.cx = 3.5;
  k.cy = 2.5;
  options.camera.intrinsics = k;
  options.camera.depth_scale = depth_scale;
  return options;
}

Eigen::Isometry3d opticalPose(int f) {
  return Eigen::Translation3d(0.1 * f, -0.2, 0.5) *
         Eigen::AngleAxisd(0.3 + 0.1 * f, Eigen::Vector3d(1, -2, 0.5).normalized());
}

// A TUM line with round-trip precision.
std::string tumLine(double t, const Eigen::Isometry3d& pose) {
  return formatTumLine({t, pose});
}

TEST(TumFolder, KnownAnswerUnprojection) {
  const fs::path dir = makeFolder("tum_known", 3);
  TumFolderOptions options = withCamera();
  options.pose_file = (dir / "poses.txt").string();
  {
    std::ofstream poses(options.pose_file);
    poses << "# timestamp tx ty tz qx qy qz qw\n";
    for (int f = 0; f < 3; ++f) poses << tumLine(10.5 + f, opticalPose(f)) << "\n";
  }
  TumFolderReader reader(dir.string(), options);
  EXPECT_EQ(reader.frames().size(), 3u);
  EXPECT_EQ(reader.poseMatching(), PoseMatching::ByOrder);
  EXPECT_EQ(reader.camera().intrinsics.width, kWidth);
  EXPECT_EQ(reader.camera().intrinsics.height, kHeight);
  EXPECT_EQ(reader.camera().depth_scale_source, "options");
  for (int f = 0; f < 3; ++f) {
    const std::optional<RangeScan> scan = reader.next();
    ASSERT_TRUE(scan);
    EXPECT_EQ(scan->index, static_cast<std::size_t>(f));
    EXPECT_EQ(scan->timestamp, 10.5 + f);
    EXPECT_TRUE(scan->range_is_depth);
    EXPECT_EQ(scan->width, kWidth);
    EXPECT_EQ(scan->height, kHeight);
    EXPECT_EQ(scan->camera.fx, 50.0);
    EXPECT_TRUE(scan->intensity.empty());
    // MRPT's sensor axes of the optical pose.
    EXPECT_TRUE(scan->sensor_pose.linear().isApprox(opticalPose(f).linear() * mrptSensorAxesInOptical(), 1e-15));
    EXPECT_EQ(scan->sensor_pose.translation(), opticalPose(f).translation());
    ASSERT_EQ(scan->points.size(), static_cast<std::size_t>(kWidth * kHeight - 1));
    for (std::size_t k = 0; k < scan->points.size(); ++k) {
      const int row = static_cast<int>(scan->pixels[k]) / kWidth, col = static_cast<int>(scan->pixels[k]) % kWidth;
      const double depth = counts(f, row, col) / 1000.0;
      EXPECT_NEAR(scan->range[scan->pixels[k]], depth, 1e-6);
      const Eigen::Vector3d optical((col - 3.5) / 50.0 * depth, (row - 2.5) / 40.0 * depth, depth);
      EXPECT_LT((scan->points[k] - opticalPose(f) * optical).norm(), 1e-6) << "frame " << f << " pixel " << k;
    }
    EXPECT_EQ(scan->range[2 * kWidth + 3], 0.0f);
  }
  EXPECT_FALSE(reader.next());
  EXPECT_EQ(reader.scansRead(), 3u);
  fs::remove_all(dir);
}

TEST(TumFolder, WithoutPosesTheOpticalFrameIsTheObjectFrame) {
  const fs::path dir = makeFolder("tum_no_poses", 1);
  TumFolderReader reader(dir.string(), withCamera(5000.0));
  EXPECT_EQ(reader.poseMatching(), PoseMatching::None);
  const auto scan = reader.next();
  ASSERT_TRUE(scan);
  EXPECT_TRUE(scan->sensor_pose.linear().isApprox(mrptSensorAxesInOptical(), 0.0));
  // Pixel (0, 0) at 1000 counts / 5000 per metre.
  ASSERT_EQ(scan->pixels[0], 0u);
  EXPECT_LT((scan->points[0] - Eigen::Vector3d(-3.5 / 50.0 * 0.2, -2.5 / 40.0 * 0.2, 0.2)).norm(), 1e-7);
  fs::remove_all(dir);
}

TEST(TumFolder, PosesMatchedByNearestTimeStamp) {
  const fs::path dir = makeFolder("tum_timestamps", 3);
  TumFolderOptions options = withCamera();
  options.pose_file = (dir / "groundtruth.txt").string();
  {
    // 100 Hz poses around the frames (10.5, 11.5, 12.5); each frame's own
    // pose is 4 ms off, the others further.
    std::ofstream poses(options.pose_file);
    for (int f = 0; f < 3; ++f) {
      poses << tumLine(10.5 + f - 0.014, opticalPose(7)) << "\n";
      poses << tumLine(10.5 + f + 0.004, opticalPose(f)) << "\n";
      poses << tumLine(10.5 + f + 0.014, opticalPose(8)) << "\n";
    }
  }
  TumFolderReader reader(dir.string(), options);
  EXPECT_EQ(reader.poseMatching(), PoseMatching::ByTimestamp);
  for (int f = 0; f < 3; ++f) {
    const auto scan = reader.next();
    ASSERT_TRUE(scan);
    EXPECT_TRUE(scan->sensor_pose.translation().isApprox(opticalPose(f).translation(), 1e-15)) << f;
  }
  // Within 3 ms nothing matches.
  options.max_time_difference = 0.003;
  const InputError e = expectInputError([&] { TumFolderReader strict(dir.string(), options); });
  EXPECT_EQ(e.source(), options.pose_file);
  EXPECT_EQ(e.location(), "scan 0");
  fs::remove_all(dir);
}

TEST(TumFolder, PoseCountMismatchNamesThePoseFileAndScan) {
  const fs::path dir = makeFolder("tum_mismatch", 3);
  TumFolderOptions options = withCamera();
  options.pose_file = (dir / "poses.txt").string();
  {
    std::ofstream poses(options.pose_file);
    poses << tumLine(10.5, opticalPose(0)) << "\n" << tumLine(11.5, opticalPose(1)) << "\n";
  }
  const InputError e = expectInputError([&] { TumFolderReader reader(dir.string(), options); });
  EXPECT_EQ(e.source(), options.pose_file);
  EXPECT_EQ(e.location(), "scan 2");
  EXPECT_NE(e.detail().find("2 poses for 3 depth frames"), std::string::npos) << e.what();
  fs::remove_all(dir);
}

TEST(TumFolder, QuaternionOffUnitLengthIsNormalisedAndCounted) {
  const fs::path dir = makeFolder("tum_quaternion", 2);
  TumFolderOptions options = withCamera();
  options.pose_file = (dir / "poses.txt").string();
  {
    std::ofstream poses(options.pose_file);
    const double c = 0.9999 * std::sqrt(0.5);
    poses.precision(17);
    poses << "10.5 0 0 0 0 0 0 1\n11.5 0 0 1 0 0 " << c << " " << c << "\n";
  }
  const std::vector<RangeScan> scans = readScans(dir.string(), [&] {
    ScanReaderOptions o;
    o.pose_file = options.pose_file;
    o.depth_camera = options.camera;
    return o;
  }());
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_FALSE(scans[0].pose_orthonormalised);
  EXPECT_TRUE(scans[1].pose_orthonormalised);
  EXPECT_LE(orthonormalityError(scans[1].sensor_pose.linear()), 1e-12);
  // 90 degrees about the optical z: the optical x axis goes to the object's y.
  const Eigen::Matrix3d optical = scans[1].sensor_pose.linear() * mrptSensorAxesInOptical().transpose();
  EXPECT_TRUE((optical * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  fs::remove_all(dir);
}

TEST(TumFolder, BadFoldersNameTheFile) {
  const fs::path dir = makeFolder("tum_bad", 3);
  const std::string list = (dir / "depth.txt").string();

  // A listed image missing: depth.txt and its line.
  fs::remove(dir / "depth" / "11.500000.png");
  InputError e = expectInputError([&] { TumFolderReader reader(dir.string(), withCamera()); });
  EXPECT_EQ(e.source(), list);
  EXPECT_EQ(e.location(), "line 4");
  EXPECT_NE(e.detail().find("11.500000.png"), std::string::npos) << e.what();

  // An 8-bit image: the image and its scan.
  cv::Mat grey(kHeight, kWidth, CV_8UC1, cv::Scalar(100));
  ASSERT_TRUE(cv::imwrite((dir / "depth" / "11.500000.png").string(), grey));
  TumFolderReader reader(dir.string(), withCamera());
  EXPECT_TRUE(reader.next());
  e = expectInputError([&] { reader.next(); });
  EXPECT_EQ(e.source(), (dir / "depth" / "11.500000.png").string());
  EXPECT_EQ(e.location(), "scan 1");
  EXPECT_NE(e.detail().find("expected a 16-bit depth image"), std::string::npos) << e.what();

  // Another size than the first frame.
  cv::Mat small(3, 4, CV_16UC1, cv::Scalar(1000));
  ASSERT_TRUE(cv::imwrite((dir / "depth" / "11.500000.png").string(), small));
  TumFolderReader resized(dir.string(), withCamera());
  EXPECT_TRUE(resized.next());
  e = expectInputError([&] { resized.next(); });
  EXPECT_EQ(e.location(), "scan 1");
  EXPECT_NE(e.detail().find("8x6"), std::string::npos) << e.what();

  // A malformed list line.
  { std::ofstream(list, std::ios::app) << "12.5\n"; }
  e = expectInputError([&] { TumFolderReader bad_list(dir.string(), withCamera()); });
  EXPECT_EQ(e.source(), list);
  EXPECT_EQ(e.location(), "line 6");

  // No intrinsics at all.
  { std::ofstream(list) << "10.5 depth/10.500000.png\n"; }
  e = expectInputError([&] { TumFolderReader no_camera(dir.string()); });
  EXPECT_EQ(e.source(), dir.string());
  EXPECT_NE(e.detail().find("intrinsics"), std::string::npos) << e.what();

  // No depth.txt.
  fs::remove(list);
  e = expectInputError([&] { TumFolderReader no_list(dir.string(), withCamera()); });
  EXPECT_EQ(e.source(), list);
  EXPECT_NE(e.detail().find("depth.txt"), std::string::npos) << e.what();
  fs::remove_all(dir);
}

TEST(TumFolder, CameraFileInTheFolder) {
  const fs::path dir = makeFolder("tum_camera_file", 1);
  const std::string camera = (dir / "camera.json").string();
  {
    std::ofstream(camera) << R"({"fx": 50, "fy": 40, "cx": 3.5, "cy": 2.5, "depth_scale": 1000, "max_range_m": 4.5,
    "distortion_k1_k2_p1_p2_k3": [0.1, 0, 0, 0, 0], "width": 8, "height": 6})";
  }
  {
    TumFolderReader reader(dir.string());
    const DepthCamera& k = reader.camera();
    EXPECT_EQ(k.camera_file, camera);
    EXPECT_EQ(k.intrinsics.fx, 50.0);
    EXPECT_EQ(k.intrinsics.distortion[0], 0.1);
    EXPECT_EQ(k.depth_scale, 1000.0);
    EXPECT_EQ(k.depth_scale_source, "camera file");
    EXPECT_FALSE(k.intrinsics_from_options);
    const auto scan = reader.next();
    ASSERT_TRUE(scan);
    EXPECT_EQ(scan->camera.distortion[0], 0.1);
    EXPECT_NEAR(scan->max_range, 4.5, 1e-6);
    EXPECT_NEAR(scan->range[0], 1.0, 1e-6);
  }
  // Options override the file; TUM's depth scale when neither gives one.
  { std::ofstream(camera) << R"({"camera": {"fx": 50, "fy": 40, "cx": 3.5, "cy": 2.5}})"; }
  {
    TumFolderReader reader(dir.string());
    EXPECT_EQ(reader.camera().depth_scale, kTumDepthScale);
    EXPECT_EQ(reader.camera().depth_scale_source, "default");
    EXPECT_NEAR(reader.next()->range[0], 1000.0 / kTumDepthScale, 1e-7);
    TumFolderReader overridden(dir.string(), withCamera(2000.0));
    EXPECT_TRUE(overridden.camera().intrinsics_from_options);
    EXPECT_EQ(overridden.camera().depth_scale, 2000.0);
  }
  // Errors name the file and the key.
  { std::ofstream(camera) << R"({"fx": 50, "fy": "forty", "cx": 3.5, "cy": 2.5})"; }
  InputError e = expectInputError([&] { TumFolderReader reader(dir.string()); });
  EXPECT_EQ(e.source(), camera);
  EXPECT_EQ(e.location(), "key fy");
  { std::ofstream(camera) << R"({"fx": 50, "fy": 40, "cx": 3.5, "cy": 2.5, "width": 640, "height": 480})"; }
  e = expectInputError([&] { TumFolderReader reader(dir.string()); });
  EXPECT_EQ(e.source(), camera);
  EXPECT_NE(e.detail().find("640x480"), std::string::npos) << e.what();
  { std::ofstream(camera) << "{not json"; }
  e = expectInputError([&] { TumFolderReader reader(dir.string()); });
  EXPECT_EQ(e.source(), camera);
  fs::remove_all(dir);
}

TEST(ScanReader, OpensRawlogsAndFolders) {
  const std::string rawlog = simulatedRecording(2, true) + "/scans.rawlog";
  ScanReader from_rawlog(rawlog);
  EXPECT_FALSE(from_rawlog.isFolder());
  EXPECT_FALSE(from_rawlog.depthCamera());
  EXPECT_EQ(from_rawlog.poseMatching(), "recorded");
  const std::vector<RangeScan> direct = readAllScans(rawlog);
  std::size_t n = 0;
  while (auto scan = from_rawlog.next()) {
    ASSERT_LT(n, direct.size());
    EXPECT_EQ(scan->points, direct[n].points);
    EXPECT_EQ(scan->sensor_pose.matrix(), direct[n].sensor_pose.matrix());
    ++n;
  }
  EXPECT_EQ(n, direct.size());

  const fs::path dir = makeFolder("scan_reader", 2);
  ScanReaderOptions options;
  options.depth_camera = withCamera().camera;
  ScanReader from_folder(dir.string(), options);
  EXPECT_TRUE(from_folder.isFolder());
  ASSERT_TRUE(from_folder.depthCamera());
  EXPECT_EQ(from_folder.depthCamera()->intrinsics.width, kWidth);
  EXPECT_EQ(from_folder.poseMatching(), "none");
  EXPECT_TRUE(from_folder.next());
  EXPECT_TRUE(from_folder.next());
  EXPECT_FALSE(from_folder.next());
  fs::remove_all(dir);
}

// The shared bunny recording: the folder and the rawlog hold the same 18
// views, the folder's poses are the rawlog's reported ones in optical axes.
TEST(TumFolder, BunnyFolderMatchesItsRawlog) {
  const std::string folder = sharedData("primesense-bunny/tum");
  const std::string rawlog = sharedData("primesense-bunny/scans.rawlog");
  const std::string mrpt_poses = sharedData("primesense-bunny/reported_poses.txt");
  if (!fs::exists(folder + "/depth.txt") || !fs::exists(rawlog) || !fs::exists(mrpt_poses))
    GTEST_SKIP() << "shared test data not found: " << folder;
  TumFolderOptions options;
  CameraIntrinsics k;
  k.fx = 542.0;
  k.fy = 540.5;
  k.cx = 320.0;
  k.cy = 240.0;
  options.camera.intrinsics = k;
  options.camera.depth_scale = 1000.0;
  options.pose_file = folder + "/reported.txt";
  TumFolderReader from_folder(folder, options);
  // The rawlog's own sensorPose matrices are not rotations (docs/rawlog.md):
  // the same poses come from its TUM file.
  RawlogReaderOptions rawlog_options;
  rawlog_options.pose_file = mrpt_poses;
  RawlogReader from_rawlog(rawlog, rawlog_options);
  std::size_t n = 0;
  while (auto scan = from_folder.next()) {
    const auto reference = from_rawlog.next();
    ASSERT_TRUE(reference) << "the rawlog has fewer scans than the folder";
    EXPECT_EQ(scan->width, 640);
    EXPECT_EQ(scan->height, 480);
    EXPECT_EQ(scan->timestamp, reference->timestamp);
    EXPECT_EQ(scan->range, reference->range) << "scan " << n;
    EXPECT_LT((scan->sensor_pose.matrix() - reference->sensor_pose.matrix()).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_EQ(scan->pixels, reference->pixels);
    ASSERT_EQ(scan->points.size(), reference->points.size());
    if (n == 0) {
      double worst = 0.0;
      for (std::size_t i = 0; i < scan->points.size(); ++i)
        worst = std::max(worst, (scan->points[i] - reference->points[i]).norm());
      EXPECT_LE(worst, 1e-6) << "first scan's points";
      EXPECT_GT(scan->points.size(), 10000u);
    }
    ++n;
  }
  EXPECT_EQ(n, 18u);
  EXPECT_FALSE(from_rawlog.next());
}

}  // namespace
}  // namespace icrkit::reconstruction
