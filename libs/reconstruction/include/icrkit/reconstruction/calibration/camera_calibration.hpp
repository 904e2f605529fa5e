#pragma once
/// \file
/// Camera calibration from checkerboard images with OpenCV: intrinsics and
/// lens distortion (Zhang's method, cv::calibrateCamera) and the pose of a
/// visible checkerboard in a calibrated image (cv::solvePnP), which seeds
/// registration in the paper's setup B (the object sits on a checkerboard
/// support).

#include <icrkit/core/camera_intrinsics.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

/// An 8-bit grey image, row-major.
struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

/// A checkerboard target; corners are the inner ones, where four squares meet.
struct Checkerboard {
  int inner_columns = 9;
  int inner_rows = 6;
  double square_size = 0.025;  ///< metres
};

struct CalibrationParameters {
  Checkerboard board;
  /// k3 is left at 0 unless asked for: with few images of a narrow lens it
  /// mostly fits noise.
  bool estimate_k3 = false;
  /// Tangential distortion (p1, p2) is estimated unless this is set.
  bool zero_tangential = false;
};

struct CalibrationResult {
  CameraIntrinsics intrinsics;
  double rms_reprojection_px = 0.0;        ///< over every corner of every used image
  std::vector<std::size_t> used_images;    ///< indices of the images where the board was found
  std::vector<Eigen::Isometry3d> board_in_camera;  ///< per used image: board frame in the optical frame
};

/// Calibrates from the images in which the whole board is found (at least
/// 3 needed). Throws InputError("images", "image N", ...) for an empty or
/// size-inconsistent image and InputError("images", "", ...) when too few
/// boards are found.
CalibrationResult calibrateCamera(const std::vector<GrayImage>& images, const CalibrationParameters& params = {});

/// The board frame (origin at the first inner corner, x along a row, y
/// along a column, z into the board) in the optical frame of a calibrated
/// image, or nothing when the board is not found. `rms_px` receives the
/// reprojection error of the corners.
std::optional<Eigen::Isometry3d> checkerboardPose(const GrayImage& image, const CameraIntrinsics& intrinsics,
                                                  const Checkerboard& board, double* rms_px = nullptr);

}  // namespace icrkit::reconstruction
