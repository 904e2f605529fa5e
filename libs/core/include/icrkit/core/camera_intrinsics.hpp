#pragma once
/// \file
/// A pinhole camera with OpenCV's (Brown-Conrady, "plumb bob") lens
/// distortion, as the sensors, the rawlogs (MRPT's TCamera) and the
/// calibration share it.

#include <array>

namespace icrkit {

/// Pixel centres sit at integer image coordinates (OpenCV's and MRPT's
/// convention): pixel (column u, row v) sees the normalised point
/// ((u - cx) / fx, (v - cy) / fy) after undistortion.
struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels
  std::array<double, 5> distortion{};     ///< k1, k2, p1, p2, k3 (normalised image coordinates)
};

}  // namespace icrkit
