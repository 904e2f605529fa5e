#pragma once
// Rendered checkerboard images with a known camera, for the calibration
// tests: an antialiased board texture warped by the plane's homography and
// resampled through the exact inverse of the lens model.

#include <icrkit/reconstruction/calibration/camera_calibration.hpp>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

namespace icrkit::reconstruction::test {

// The camera the images are rendered with: a Kinect-like 640 x 480 with
// noticeable barrel distortion.
inline CameraIntrinsics truth() {
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
inline DistortionMap distortionMap(const CameraIntrinsics& k) {
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
inline GrayImage render(const Checkerboard& board, const Eigen::Isometry3d& board_in_camera, const CameraIntrinsics& k,
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

inline Eigen::Isometry3d boardPose(double roll, double pitch, double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = t;
  return p;
}


// Twelve board poses, tilted every way and spread over the image,
// 0.45-0.65 m away: the distortion shows towards the corners.
inline std::vector<Eigen::Isometry3d> boardPoses() {
  const double tilts[][3] = {{0.0, 0.0, 0.0},   {0.35, 0.0, 0.1},  {-0.35, 0.05, -0.1}, {0.0, 0.4, 0.05},
                             {0.05, -0.4, 0.0}, {0.3, 0.3, 0.2},   {-0.3, -0.3, -0.2}, {0.25, -0.25, 0.4},
                             {-0.2, 0.3, -0.4}, {0.15, 0.15, 1.5}, {0.4, -0.1, 0.0},   {-0.1, 0.45, 0.3}};
  const double shifts[][3] = {{-0.10, -0.07, 0.50}, {-0.02, -0.05, 0.55}, {-0.16, -0.02, 0.52}, {-0.12, -0.10, 0.48},
                              {-0.05, -0.02, 0.60}, {-0.14, -0.08, 0.58}, {-0.06, -0.03, 0.50}, {-0.11, -0.09, 0.62},
                              {-0.07, -0.04, 0.53}, {0.03, -0.08, 0.56},  {-0.15, -0.06, 0.45}, {-0.09, -0.11, 0.65}};
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 12; ++i)
    poses.push_back(boardPose(tilts[i][0], tilts[i][1], tilts[i][2],
                              Eigen::Vector3d(shifts[i][0], shifts[i][1], shifts[i][2])));
  return poses;
}

}  // namespace icrkit::reconstruction::test
