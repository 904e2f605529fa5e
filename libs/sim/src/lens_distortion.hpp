#pragma once
/// \file
/// OpenCV's Brown-Conrady lens model (k1, k2, p1, p2, k3) on normalised
/// image coordinates, and its inverse by Newton's method: the rays of a
/// distorted camera's pixels, for rendering and for unprojection alike.

#include <icrkit/sim/range_sensor.hpp>

#include <Eigen/Core>

#include <array>

namespace icrkit::sim {

/// Where the lens images the normalised point (x, y) = (X/Z, Y/Z).
Eigen::Vector2d distortNormalised(const std::array<double, 5>& k, const Eigen::Vector2d& undistorted);

/// The normalised point that the lens images at `distorted`, to about 1e-15
/// relative. False when Newton's method does not converge (a point outside
/// the region where the model is invertible); `undistorted` is then NaN.
bool undistortNormalised(const std::array<double, 5>& k, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d& undistorted);

/// True when the lens model is locally invertible (positive Jacobian
/// determinant) all along the segment from the optical axis to the
/// normalised point `undistorted`: no fold of the model lies closer to the
/// centre, so that point's undistortion is the physical one.
bool monotoneAlongRadius(const std::array<double, 5>& k, const Eigen::Vector2d& undistorted);

/// Direction (x, y, 1) in the optical frame of the ray through image point
/// (u, v) in pixels; NaN where the distortion cannot be inverted.
Eigen::Vector3d pixelDirection(const CameraIntrinsics& intrinsics, double u, double v);

}  // namespace icrkit::sim
