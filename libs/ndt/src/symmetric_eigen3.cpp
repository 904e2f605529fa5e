#include <icrkit/ndt/symmetric_eigen3.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace icrkit::ndt {
namespace {

// A unit vector spanning the null space of (A - l I), from the largest cross
// product of its rows; false when the rows are (numerically) all parallel.
bool nullVector(const Eigen::Matrix3d& a, double l, Eigen::Vector3d& out) {
  const Eigen::Matrix3d m = a - l * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d c[3] = {m.row(0).cross(m.row(1)), m.row(0).cross(m.row(2)), m.row(1).cross(m.row(2))};
  int best = 0;
  double best_norm = c[0].squaredNorm();
  for (int k = 1; k < 3; ++k)
    if (c[k].squaredNorm() > best_norm) {
      best = k;
      best_norm = c[k].squaredNorm();
    }
  if (!(best_norm > 0)) return false;
  out = c[best] / std::sqrt(best_norm);
  return true;
}

// Any unit vector orthogonal to the unit vector n.
Eigen::Vector3d orthogonalTo(const Eigen::Vector3d& n) {
  const Eigen::Vector3d other = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(other).normalized();
}

}  // namespace

SymmetricEigen3 eigenSymmetric3(const Eigen::Matrix3d& input) {
  SymmetricEigen3 result;
  // Scale to unit magnitude so that squares neither overflow nor underflow.
  const double scale = input.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) {
    result.values.setZero();
    result.vectors.setIdentity();
    return result;
  }
  const Eigen::Matrix3d a = input / scale;
  const double p1 = a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) + a(1, 2) * a(1, 2);
  const double q = a.trace() / 3.0;
  const double p2 = (a(0, 0) - q) * (a(0, 0) - q) + (a(1, 1) - q) * (a(1, 1) - q) + (a(2, 2) - q) * (a(2, 2) - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  if (!(p > 0)) {  // a multiple of the identity: every basis is an eigenbasis
    result.values = Eigen::Vector3d::Constant(q * scale);
    result.vectors.setIdentity();
    return result;
  }
  const Eigen::Matrix3d b = (a - q * Eigen::Matrix3d::Identity()) / p;
  const double r = std::clamp(b.determinant() / 2.0, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double l1 = q + 2.0 * p * std::cos(phi);
  const double l3 = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  const double l2 = 3.0 * q - l1 - l3;

  // The eigenvalue with the larger gap to the middle one has a well-defined
  // vector: take it from the null space of (A - l I), then solve the 2x2
  // problem in the plane orthogonal to it for the other two.
  const bool first_isolated = (l1 - l2) >= (l2 - l3);
  Eigen::Vector3d isolated;
  if (!nullVector(a, first_isolated ? l1 : l3, isolated)) isolated = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d x = orthogonalTo(isolated);
  const Eigen::Vector3d y = isolated.cross(x);
  const double m00 = x.dot(a * x), m01 = x.dot(a * y), m11 = y.dot(a * y);
  // Rotation angle that diagonalises [[m00, m01], [m01, m11]]; (c, s) is the
  // vector of its larger eigenvalue.
  const double theta = 0.5 * std::atan2(2.0 * m01, m00 - m11);
  const double c = std::cos(theta), s = std::sin(theta);
  const Eigen::Vector3d larger = c * x + s * y;
  const Eigen::Vector3d smaller = -s * x + c * y;
  Eigen::Vector3d v1, v2, v3;
  if (first_isolated) {
    v1 = isolated;
    v2 = larger;
    v3 = smaller;
  } else {
    v3 = isolated;
    v1 = larger;
    v2 = smaller;
  }
  if (v1.cross(v2).dot(v3) < 0) v2 = -v2;  // right-handed
  // Rayleigh quotients are accurate to the square of the vector error.
  Eigen::Vector3d values(v1.dot(a * v1), v2.dot(a * v2), v3.dot(a * v3));
  values(1) = std::clamp(values(1), values(2), values(0));
  result.values = values * scale;
  result.vectors.col(0) = v1;
  result.vectors.col(1) = v2;
  result.vectors.col(2) = v3;
  return result;
}

}  // namespace icrkit::ndt
