#include "lens_distortion.hpp"

#include <cmath>
#include <limits>

namespace icrkit::sim {

Eigen::Vector2d distortNormalised(const std::array<double, 5>& k, const Eigen::Vector2d& undistorted) {
  const double x = undistorted.x(), y = undistorted.y();
  const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

namespace {
Eigen::Matrix2d distortionJacobian(const std::array<double, 5>& k, const Eigen::Vector2d& p) {
  const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double d_radial = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);  // d radial / d r2
  Eigen::Matrix2d jacobian;
  jacobian << radial + 2.0 * x * x * d_radial + 2.0 * p1 * y + 6.0 * p2 * x,
      2.0 * x * y * d_radial + 2.0 * p1 * x + 2.0 * p2 * y, 2.0 * x * y * d_radial + 2.0 * p1 * x + 2.0 * p2 * y,
      radial + 2.0 * y * y * d_radial + 6.0 * p1 * y + 2.0 * p2 * x;
  return jacobian;
}
}  // namespace

bool monotoneAlongRadius(const std::array<double, 5>& k, const Eigen::Vector2d& undistorted) {
  if (!undistorted.allFinite()) return false;
  constexpr int kSteps = 512;
  for (int i = 0; i <= kSteps; ++i)
    if (!(distortionJacobian(k, undistorted * (static_cast<double>(i) / kSteps)).determinant() > 0.0)) return false;
  return true;
}

bool undistortNormalised(const std::array<double, 5>& k, const Eigen::Vector2d& distorted,
                         Eigen::Vector2d& undistorted) {
  // OpenCV's fixed-point iteration converges slowly (or not at all) for a
  // strong barrel distortion such as the SR4000's; Newton's method with the
  // analytic Jacobian reaches double precision in a handful of steps, and a
  // backtracking step keeps it from overshooting near the image corners.
  Eigen::Vector2d p = distorted;
  Eigen::Vector2d residual = distortNormalised(k, p) - distorted;
  const double tolerance = 1e-15 * (1.0 + distorted.norm());
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Eigen::Matrix2d jacobian = distortionJacobian(k, p);
    // Beyond a fold of the lens model (Jacobian determinant <= 0) a root
    // would be a second, unphysical preimage: the pixel has no ray.
    const double det = jacobian.determinant();
    if (!(det > 1e-12)) break;
    if (residual.norm() <= tolerance) {
      undistorted = p;
      return true;
    }
    const Eigen::Vector2d step = jacobian.inverse() * residual;
    double scale = 1.0;
    Eigen::Vector2d next = p - step;
    Eigen::Vector2d next_residual = distortNormalised(k, next) - distorted;
    while (next_residual.norm() >= residual.norm() && scale > 1e-6) {
      scale *= 0.5;
      next = p - scale * step;
      next_residual = distortNormalised(k, next) - distorted;
    }
    if (next_residual.norm() >= residual.norm()) {
      // No progress: converged to rounding, or stuck.
      if (residual.norm() <= 1e-12 * (1.0 + distorted.norm())) {
        undistorted = p;
        return true;
      }
      break;
    }
    p = next;
    residual = next_residual;
  }
  undistorted = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return false;
}

Eigen::Vector3d pixelDirection(const CameraIntrinsics& intrinsics, double u, double v) {
  const Eigen::Vector2d distorted((u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy);
  Eigen::Vector2d undistorted;
  undistortNormalised(intrinsics.distortion, distorted, undistorted);  // NaN when it fails
  return {undistorted.x(), undistorted.y(), 1.0};
}

}  // namespace icrkit::sim
