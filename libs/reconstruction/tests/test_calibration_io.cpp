#include <icrkit/reconstruction/calibration/calibration_images.hpp>
#include <icrkit/reconstruction/input/rawlog_intrinsics.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/sim/dataset.hpp>

#include "checkerboard_images.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("icrkit_calibration_io_" + name + "_" + std::to_string(::getpid()));
}

TEST(ImageFiles, CalibratesFromAFolderOfImages) {
  const CameraIntrinsics k = test::truth();
  const test::DistortionMap map = test::distortionMap(k);
  const Checkerboard board;
  const fs::path dir = scratch("folder");
  fs::create_directories(dir);
  const std::vector<Eigen::Isometry3d> poses = test::boardPoses();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const GrayImage g = test::render(board, poses[i], k, map);
    const cv::Mat m(g.height, g.width, CV_8UC1, const_cast<std::uint8_t*>(g.pixels.data()));
    // PNG and PGM both; names sort in the order written.
    const std::string name = "board_" + std::string(i < 10 ? "0" : "") + std::to_string(i) + (i % 2 ? ".pgm" : ".png");
    ASSERT_TRUE(cv::imwrite((dir / name).string(), m));
  }
  std::ofstream(dir / "notes.txt") << "not an image";
  std::vector<std::string> names;
  const std::vector<GrayImage> images = readGrayImages(dir.string(), &names);
  ASSERT_EQ(images.size(), poses.size());
  EXPECT_EQ(names.front(), "board_00.png");
  EXPECT_EQ(images[3].pixels, test::render(board, poses[3], k, map).pixels);  // lossless round trip
  const CalibrationResult r = calibrateCamera(images, {board});
  EXPECT_LT(r.rms_reprojection_px, 0.5);
  EXPECT_NEAR(r.intrinsics.fx, k.fx, 0.01 * k.fx);
  EXPECT_NEAR(r.intrinsics.cy, k.cy, 0.01 * k.cy);

  std::ofstream(dir / "z_broken.png") << "not a png";
  EXPECT_THROW(readGrayImages(dir.string()), InputError);
  EXPECT_THROW(readGrayImages((dir / "missing").string()), InputError);
  fs::create_directories(dir / "empty");
  EXPECT_THROW(readGrayImages((dir / "empty").string()), InputError);
  fs::remove_all(dir);
}

TEST(ImageFiles, GreyFromColour) {
  Image8 rgb;
  rgb.width = 2;
  rgb.height = 1;
  rgb.channels = 3;
  rgb.data = {255, 0, 0, 255, 255, 255};
  const GrayImage g = grayOf(rgb);
  ASSERT_EQ(g.pixels.size(), 2u);
  EXPECT_EQ(g.pixels[0], 76);  // 0.299 * 255
  EXPECT_EQ(g.pixels[1], 255);
}

TEST(RawlogIntrinsics, WritesTheCalibratedCameraIntoACopy) {
  sim::DatasetSpec spec;
  spec.object = "cup";
  spec.sensor = sim::SensorType::Kinect;
  spec.acquisition.views = 2;
  const fs::path dir = scratch("rawlog");
  sim::simulateDataset(spec, dir.string());
  const std::string in = (dir / "scans.rawlog").string(), out = (dir / "calibrated.rawlog").string();
  const std::vector<RangeScan> before = readAllScans(in);
  CameraIntrinsics k = before[0].camera;
  k.fx *= 1.01;
  k.distortion[0] = -0.05;
  EXPECT_EQ(writeRawlogWithIntrinsics(in, out, k), 2u);
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  const std::vector<RangeScan> after = readAllScans(out);
  ASSERT_EQ(after.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_DOUBLE_EQ(after[i].camera.fx, k.fx);
    EXPECT_DOUBLE_EQ(after[i].camera.distortion[0], -0.05);
    EXPECT_DOUBLE_EQ(after[i].camera_intensity.fx, k.fx);
    EXPECT_EQ(after[i].range, before[i].range);
    EXPECT_TRUE(after[i].sensor_pose.isApprox(before[i].sensor_pose, 0.0));
  }
  // A camera of another size, a truncated input: clear errors, no output.
  CameraIntrinsics small = k;
  small.width = 320;
  const std::string bad = (dir / "bad.rawlog").string();
  EXPECT_THROW(writeRawlogWithIntrinsics(in, bad, small), InputError);
  std::string bytes;
  {
    std::ifstream f(in, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  std::ofstream((dir / "cut.rawlog").string(), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(writeRawlogWithIntrinsics((dir / "cut.rawlog").string(), bad, k), InputError);
  EXPECT_FALSE(fs::exists(bad));
  EXPECT_FALSE(fs::exists(bad + ".tmp"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace icrkit::reconstruction
