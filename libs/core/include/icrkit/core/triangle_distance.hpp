#pragma once
/// \file
/// Closest point on a triangle, in double precision.

#include <Eigen/Core>

namespace icrkit {

struct TrianglePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double u = 0.0, v = 0.0;  ///< barycentrics: point = (1-u-v) a + u b + v c, all three in [0, 1]
  double distance = 0.0;    ///< from the query, metres
};

/// The point of triangle (a, b, c) closest to `p`. Degenerate triangles
/// (collinear or coincident corners) are handled as the segments or the
/// point they collapse to. Exact up to double rounding: `distance` is
/// |p - point| of the returned point.
TrianglePoint closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                     const Eigen::Vector3d& c);

}  // namespace icrkit
