#include <icrkit/core/triangle_distance.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace icrkit {
namespace {

// Parameter in [0, 1] of the point of segment start -> start + edge closest
// to p; a zero-length segment is its start point.
double segmentParameter(const Eigen::Vector3d& p, const Eigen::Vector3d& start, const Eigen::Vector3d& edge) {
  const double length2 = edge.squaredNorm();
  if (!(length2 > 0.0)) return 0.0;
  return std::clamp((p - start).dot(edge) / length2, 0.0, 1.0);
}

}  // namespace

TrianglePoint closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                     const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const Eigen::Vector3d n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  // Without a plane (degenerate corners) every edge is a candidate:
  // collinear corners span exactly the union of the three edges.
  bool on_ab = true, on_ac = true, on_bc = true;
  if (n2 > 0.0) {
    // Barycentrics of p's projection onto the plane. The component of ap
    // along n drops out of both triple products, so no explicit projection
    // (and its rounding) is needed.
    const double u = ap.cross(ac).dot(n) / n2;
    const double v = ab.cross(ap).dot(n) / n2;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0) {
      TrianglePoint inside;
      inside.u = u;
      inside.v = v;
      inside.point = a + u * ab + v * ac;
      inside.distance = (p - inside.point).norm();
      return inside;
    }
    // Outside, the closest point lies on an edge whose line separates the
    // projection from the triangle: one with a negative barycentric. (An
    // overflow to NaN flags none; then all three are tried.)
    const bool flagged[3] = {v < 0.0, u < 0.0, u + v > 1.0};
    if (flagged[0] || flagged[1] || flagged[2]) {
      on_ab = flagged[0];
      on_ac = flagged[1];
      on_bc = flagged[2];
    }
  }
  TrianglePoint best;
  double best2 = std::numeric_limits<double>::infinity();
  auto consider = [&](const Eigen::Vector3d& start, const Eigen::Vector3d& edge, double u_start, double v_start,
                      double u_end, double v_end) {
    const double t = segmentParameter(p, start, edge);
    const Eigen::Vector3d point = start + t * edge;
    const double d2 = (p - point).squaredNorm();
    if (!(d2 < best2)) return;  // ties keep the earlier edge
    best2 = d2;
    best.point = point;
    best.u = (1.0 - t) * u_start + t * u_end;
    best.v = (1.0 - t) * v_start + t * v_end;
  };
  if (on_ab) consider(a, ab, 0.0, 0.0, 1.0, 0.0);
  if (on_ac) consider(a, ac, 0.0, 0.0, 0.0, 1.0);
  if (on_bc) consider(b, c - b, 1.0, 0.0, 0.0, 1.0);
  best.distance = std::sqrt(best2);
  return best;
}

}  // namespace icrkit
