#pragma once
// The line-triangle test shared by Algorithm 2 and the brute-force mappings.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace icrkit::eval::detail {

/// Whether the full line origin + t direction meets triangle abc, edges and
/// corners included within `tolerance` (barycentric units), in double
/// precision; `t` receives the crossing. A line parallel to the face (to
/// 1e-14 relative) meets nothing.
inline bool lineMeetsTriangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c, double tolerance, double& t) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = direction.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm() * direction.norm()) return false;
  const Eigen::Vector3d s = origin - a;
  const double u = s.dot(h) / det;
  if (u < -tolerance || u > 1.0 + tolerance) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = direction.dot(q) / det;
  if (v < -tolerance || u + v > 1.0 + tolerance) return false;
  t = e2.dot(q) / det;
  return true;
}

}  // namespace icrkit::eval::detail
