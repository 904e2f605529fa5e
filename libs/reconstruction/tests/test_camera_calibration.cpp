#include <icrkit/reconstruction/calibration/camera_calibration.hpp>

#include <icrkit/core/error.hpp>

#include "checkerboard_images.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace icrkit::reconstruction {
namespace {

using namespace test;

// Where the lens moves the ideal image point of pixel (u, v) of the truth
// camera, in pixels: distorted minus undistorted.
Eigen::Vector2d lensShift(const CameraIntrinsics& k, double u, double v) {
  const CameraIntrinsics t = truth();
  const double x = (u - t.cx) / t.fx, y = (v - t.cy) / t.fy;
  const double r2 = x * x + y * y;
  const auto& d = k.distortion;
  const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  return {k.fx * (xd - x), k.fy * (yd - y)};
}

TEST(CameraCalibration, RecoversKnownIntrinsicsFromRenderedBoards) {
  const CameraIntrinsics k = truth();
  const DistortionMap map = distortionMap(k);
  Checkerboard board;  // 9 x 6 inner corners, 25 mm squares
  std::vector<GrayImage> images;
  const std::vector<Eigen::Isometry3d> poses = boardPoses();
  for (const Eigen::Isometry3d& pose : poses) images.push_back(render(board, pose, k, map));
  const CalibrationResult r = calibrateCamera(images, {board});
  std::cout << "calibration: " << r.used_images.size() << " boards, rms " << r.rms_reprojection_px << " px, fx "
            << r.intrinsics.fx << " fy " << r.intrinsics.fy << " cx " << r.intrinsics.cx << " cy " << r.intrinsics.cy
            << " k1 " << r.intrinsics.distortion[0] << " k2 " << r.intrinsics.distortion[1] << "\n";
  ASSERT_GE(r.used_images.size(), 10u);
  EXPECT_LT(r.rms_reprojection_px, 0.5);
  EXPECT_NEAR(r.intrinsics.fx, k.fx, 0.01 * k.fx);
  EXPECT_NEAR(r.intrinsics.fy, k.fy, 0.01 * k.fy);
  EXPECT_NEAR(r.intrinsics.cx, k.cx, 0.01 * k.cx);
  EXPECT_NEAR(r.intrinsics.cy, k.cy, 0.01 * k.cy);
  // k1 and k2 trade off against each other; what must agree is where the
  // lens puts a point, over the part of the image the boards covered (the
  // extreme corners are extrapolation: 4.6 px apart there).
  double worst = 0;
  for (double u : {100.0, 200.0, 320.0, 440.0, 540.0})
    for (double v : {80.0, 160.0, 240.0, 320.0, 400.0}) {
      const Eigen::Vector2d a = lensShift(k, u, v), b = lensShift(r.intrinsics, u, v);
      worst = std::max(worst, (a - b).norm());
    }
  std::cout << "largest disagreement of the two lens models: " << worst << " px\n";
  EXPECT_LT(worst, 0.5);

  // The board's pose in a calibrated image: within a millimetre and a
  // few tenths of a degree of the one it was rendered at.
  double rms = 0;
  const auto pose = checkerboardPose(images[5], r.intrinsics, board, &rms);
  ASSERT_TRUE(pose.has_value());
  EXPECT_LT(rms, 0.5);
  EXPECT_LT((pose->translation() - poses[5].translation()).norm(), 0.001);
  EXPECT_LT(Eigen::AngleAxisd(pose->linear().transpose() * poses[5].linear()).angle(), 0.003);
}

TEST(CameraCalibration, BadInput) {
  GrayImage blank;
  blank.width = 64;
  blank.height = 48;
  blank.pixels.assign(64 * 48, 128);
  EXPECT_THROW(calibrateCamera({}), InputError);
  EXPECT_THROW(calibrateCamera({blank, blank, blank}), InputError);  // no board anywhere
  GrayImage broken = blank;
  broken.pixels.resize(10);
  EXPECT_THROW(calibrateCamera({blank, broken}), InputError);
  GrayImage other = blank;
  other.width = 48;
  other.height = 64;
  EXPECT_THROW(calibrateCamera({blank, other}), InputError);
  CameraIntrinsics k = truth();
  EXPECT_FALSE(checkerboardPose(blank, k, {}).has_value());
  EXPECT_THROW(checkerboardPose(blank, k, {1, 6, 0.02}), InputError);
}

}  // namespace
}  // namespace icrkit::reconstruction
