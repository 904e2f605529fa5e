#include <icrkit/reconstruction/camera_calibration.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

namespace icrkit::reconstruction {
namespace {

// The camera the images are rendered with: a Kinect-like 640 x 480 with
// noticeable barrel distortion.
CameraIntrinsics truth() {
  CameraIntrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = 580.0;
  k.fy = 578.0;
  k.cx = 322.5;
  k.cy = 236.0;
  k.distortion = {-0.21, 0.09, 0.0008, -0.0006, 0.0};
  return k;
}

// For every pixel of the distorted image, where it sees in the ideal
// (undistorted) image: the image is rendered without distortion and then
// resampled through this map.
struct DistortionMap {
  cv::Mat x, y;
};
DistortionMap distortionMap(const CameraIntrinsics& k) {
  std::vector<cv::Point2f> pixels;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  const cv::Mat K = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(k.distortion.data()));
  std::vector<cv::Point2f> ideal;
  // OpenCV's default stops after 5 fixed-point steps, far from converged
  // near the corners for this much distortion.
  cv::undistortPoints(pixels, ideal, K, D, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
  DistortionMap map{cv::Mat(k.height, k.width, CV_32F), cv::Mat(k.height, k.width, CV_32F)};
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      map.x.at<float>(v, u) = ideal[static_cast<std::size_t>(v * k.width + u)].x;
      map.y.at<float>(v, u) = ideal[static_cast<std::size_t>(v * k.width + u)].y;
    }
  return map;
}

// The board seen from `board_in_camera`: a high-resolution texture (white
// margin of one square around the squares) warped by the plane's
// homography, then distorted.
GrayImage render(const Checkerboard& board, const Eigen::Isometry3d& board_in_camera, const CameraIntrinsics& k,
                 const DistortionMap& map) {
  const double px_per_m = 4000.0;  // texture resolution: 0.25 mm per texel
  const int cols = board.inner_columns + 1, rows = board.inner_rows + 1;
  const double margin = board.square_size;
  const int tw = static_cast<int>((cols * board.square_size + 2 * margin) * px_per_m);
  const int th = static_cast<int>((rows * board.square_size + 2 * margin) * px_per_m);
  cv::Mat texture(th, tw, CV_8U, cv::Scalar(235));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if ((r + c) % 2 == 0) {
        const int x0 = static_cast<int>((margin + c * board.square_size) * px_per_m);
        const int y0 = static_cast<int>((margin + r * board.square_size) * px_per_m);
        const int s = static_cast<int>(board.square_size * px_per_m);
        texture(cv::Rect(x0, y0, s, s)).setTo(20);
      }
  // A camera pixel spans about 3-4 texels here: blurring the texture by
  // about that much stands in for the pixel's area integration.
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 1.5);
  // Texel (tx, ty) -> board point (tx / ppm - margin - square, ...): the
  // board frame's origin is the first inner corner.
  const cv::Mat texel_to_board = (cv::Mat_<double>(3, 3) << 1 / px_per_m, 0, -(margin + board.square_size), 0,
                                  1 / px_per_m, -(margin + board.square_size), 0, 0, 1);
  const Eigen::Matrix3d& R = board_in_camera.linear();
  const Eigen::Vector3d& t = board_in_camera.translation();
  const cv::Mat board_to_image = (cv::Mat_<double>(3, 3) << k.fx * R(0, 0) + k.cx * R(2, 0),
                                  k.fx * R(0, 1) + k.cx * R(2, 1), k.fx * t(0) + k.cx * t(2),
                                  k.fy * R(1, 0) + k.cy * R(2, 0), k.fy * R(1, 1) + k.cy * R(2, 1),
                                  k.fy * t(1) + k.cy * t(2), R(2, 0), R(2, 1), t(2));
  cv::Mat ideal;
  cv::warpPerspective(texture, ideal, board_to_image * texel_to_board, cv::Size(k.width, k.height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(120));
  cv::Mat distorted;
  cv::remap(ideal, distorted, map.x, map.y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(120));
  GrayImage image;
  image.width = k.width;
  image.height = k.height;
  image.pixels.assign(distorted.datastart, distorted.dataend);
  return image;
}

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

Eigen::Isometry3d boardPose(double roll, double pitch, double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = t;
  return p;
}

TEST(CameraCalibration, RecoversKnownIntrinsicsFromRenderedBoards) {
  const CameraIntrinsics k = truth();
  const DistortionMap map = distortionMap(k);
  Checkerboard board;  // 9 x 6 inner corners, 25 mm squares
  std::vector<GrayImage> images;
  std::vector<Eigen::Isometry3d> poses;
  // Boards tilted every way and spread over the image, 0.45-0.7 m away:
  // the distortion shows towards the corners.
  const double tilts[][3] = {{0.0, 0.0, 0.0},   {0.35, 0.0, 0.1},  {-0.35, 0.05, -0.1}, {0.0, 0.4, 0.05},
                             {0.05, -0.4, 0.0}, {0.3, 0.3, 0.2},   {-0.3, -0.3, -0.2}, {0.25, -0.25, 0.4},
                             {-0.2, 0.3, -0.4}, {0.15, 0.15, 1.5}, {0.4, -0.1, 0.0},   {-0.1, 0.45, 0.3}};
  const double shifts[][3] = {{-0.10, -0.07, 0.50}, {-0.02, -0.05, 0.55}, {-0.16, -0.02, 0.52}, {-0.12, -0.10, 0.48},
                              {-0.05, -0.02, 0.60}, {-0.14, -0.08, 0.58}, {-0.06, -0.03, 0.50}, {-0.11, -0.09, 0.62},
                              {-0.07, -0.04, 0.53}, {0.03, -0.08, 0.56},  {-0.15, -0.06, 0.45}, {-0.09, -0.11, 0.65}};
  for (int i = 0; i < 12; ++i) {
    poses.push_back(boardPose(tilts[i][0], tilts[i][1], tilts[i][2],
                              Eigen::Vector3d(shifts[i][0], shifts[i][1], shifts[i][2])));
    images.push_back(render(board, poses.back(), k, map));
  }
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
