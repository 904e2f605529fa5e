#include <icrkit/reconstruction/calibration/camera_calibration.hpp>

#include <icrkit/core/error.hpp>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <string>

namespace icrkit::reconstruction {
namespace {

cv::Mat wrap(const GrayImage& image) {
  // OpenCV only reads it; the const_cast avoids a copy.
  return cv::Mat(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
}

void checkImage(const GrayImage& image, std::size_t index) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw InputError("images", "image " + std::to_string(index),
                     "expected width x height grey pixels, got " + std::to_string(image.pixels.size()) + " for " +
                         std::to_string(image.width) + " x " + std::to_string(image.height));
}

void checkBoard(const Checkerboard& board) {
  if (board.inner_columns < 2 || board.inner_rows < 2 || !(board.square_size > 0) || !std::isfinite(board.square_size))
    throw InputError("Checkerboard", "", "expected at least 2 x 2 inner corners and a square size > 0 m");
}

std::vector<cv::Point3f> boardCorners(const Checkerboard& board) {
  std::vector<cv::Point3f> corners;
  for (int r = 0; r < board.inner_rows; ++r)
    for (int c = 0; c < board.inner_columns; ++c)
      corners.emplace_back(static_cast<float>(c * board.square_size), static_cast<float>(r * board.square_size), 0.0f);
  return corners;
}

bool findCorners(const cv::Mat& gray, const Checkerboard& board, std::vector<cv::Point2f>& corners) {
  const cv::Size pattern(board.inner_columns, board.inner_rows);
  if (!cv::findChessboardCorners(gray, pattern, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return false;
  // Sub-pixel refinement: the corner detector alone is good to about a pixel.
  cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
  return true;
}

cv::Mat cameraMatrix(const CameraIntrinsics& k) {
  return (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
}

Eigen::Isometry3d poseOf(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose.linear()(i, j) = r.at<double>(i, j);
    pose.translation()(i) = tvec.at<double>(i);
  }
  return pose;
}

}  // namespace

CalibrationResult calibrateCamera(const std::vector<GrayImage>& images, const CalibrationParameters& params) {
  checkBoard(params.board);
  if (images.empty()) throw InputError("images", "", "no images to calibrate from");
  for (std::size_t i = 0; i < images.size(); ++i) {
    checkImage(images[i], i);
    if (images[i].width != images[0].width || images[i].height != images[0].height)
      throw InputError("images", "image " + std::to_string(i), "size differs from image 0");
  }
  const std::vector<cv::Point3f> model = boardCorners(params.board);
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  CalibrationResult result;
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::vector<cv::Point2f> corners;
    if (!findCorners(wrap(images[i]), params.board, corners)) continue;
    object_points.push_back(model);
    image_points.push_back(corners);
    result.used_images.push_back(i);
  }
  if (image_points.size() < 3)
    throw InputError("images", "",
                     "the " + std::to_string(params.board.inner_columns) + " x " +
                         std::to_string(params.board.inner_rows) + " checkerboard was found in " +
                         std::to_string(image_points.size()) + " of " + std::to_string(images.size()) +
                         " images; calibration needs at least 3");
  int flags = 0;
  if (!params.estimate_k3) flags |= cv::CALIB_FIX_K3;
  if (params.zero_tangential) flags |= cv::CALIB_ZERO_TANGENT_DIST;
  cv::Mat k, d;
  std::vector<cv::Mat> rvecs, tvecs;
  result.rms_reprojection_px = cv::calibrateCamera(object_points, image_points,
                                                   cv::Size(images[0].width, images[0].height), k, d, rvecs, tvecs,
                                                   flags);
  CameraIntrinsics& in = result.intrinsics;
  in.width = images[0].width;
  in.height = images[0].height;
  in.fx = k.at<double>(0, 0);
  in.fy = k.at<double>(1, 1);
  in.cx = k.at<double>(0, 2);
  in.cy = k.at<double>(1, 2);
  for (int j = 0; j < 5 && j < static_cast<int>(d.total()); ++j) in.distortion[static_cast<std::size_t>(j)] = d.at<double>(j);
  for (std::size_t i = 0; i < rvecs.size(); ++i) result.board_in_camera.push_back(poseOf(rvecs[i], tvecs[i]));
  return result;
}

std::optional<Eigen::Isometry3d> checkerboardPose(const GrayImage& image, const CameraIntrinsics& intrinsics,
                                                  const Checkerboard& board, double* rms_px) {
  checkBoard(board);
  checkImage(image, 0);
  std::vector<cv::Point2f> corners;
  if (!findCorners(wrap(image), board, corners)) return std::nullopt;
  const std::vector<cv::Point3f> model = boardCorners(board);
  const cv::Mat k = cameraMatrix(intrinsics);
  const cv::Mat d(1, 5, CV_64F, const_cast<double*>(intrinsics.distortion.data()));
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(model, corners, k, d, rvec, tvec, false, cv::SOLVEPNP_ITERATIVE)) return std::nullopt;
  if (rms_px) {
    std::vector<cv::Point2f> projected;
    cv::projectPoints(model, rvec, tvec, k, d, projected);
    double sum = 0;
    for (std::size_t i = 0; i < projected.size(); ++i) {
      const cv::Point2f e = projected[i] - corners[i];
      sum += e.x * e.x + e.y * e.y;
    }
    *rms_px = std::sqrt(sum / static_cast<double>(projected.size()));
  }
  return poseOf(rvec, tvec);
}

}  // namespace icrkit::reconstruction
