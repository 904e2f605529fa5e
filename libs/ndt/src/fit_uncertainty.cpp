#include <icrkit/ndt/fit_uncertainty.hpp>

#include <algorithm>
#include <cmath>

namespace icrkit::ndt {

FitUncertainty planeFitUncertainty(const Eigen::Vector3d& eigenvalues, const Eigen::Matrix3d& axes, std::size_t count,
                                   const Eigen::Vector3d& offset, double radius, FittedPoint point) {
  const double l1 = eigenvalues(0), l2 = eigenvalues(1), l3 = std::max(eigenvalues(2), 0.0);
  FitUncertainty u;
  if (count < 4 || !(l2 > 0) || !(l1 > 0)) {
    u.normal_sigma = M_PI / 2;
    u.position_sigma = radius;
    return u;
  }
  const double k = static_cast<double>(count);
  const double noise = l3 * k / (k - 3.0);  // s^2
  // Beyond a right angle the tilt model means nothing: the normal is unknown.
  u.normal_sigma = std::min(M_PI / 2, std::sqrt(noise / k * (1.0 / l1 + 1.0 / l2)));
  if (point == FittedPoint::Measured) {
    u.position_sigma = std::sqrt(noise);
  } else {
    const double a1 = offset.dot(axes.col(0)), a2 = offset.dot(axes.col(1));
    u.position_sigma = std::sqrt(noise / k * (1.0 + a1 * a1 / l1 + a2 * a2 / l2));
  }
  u.position_sigma = std::min(u.position_sigma, radius);
  return u;
}

}  // namespace icrkit::ndt
