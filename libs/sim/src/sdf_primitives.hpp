#pragma once
/// \file
/// Signed distance functions (negative inside, metres) of the primitives the
/// CAD objects are built from, and the CSG operations that combine them.
///
/// The exact distances follow Inigo Quilez's catalogue
/// (iquilezles.org/articles/distfunctions). The mesher only needs the sign
/// and a continuous field, but near-exact distances keep the smooth-union
/// blend widths and the projection of extra vertices meaningful. Solids of
/// revolution about the z axis are 2D profiles in (rho, z), rho = sqrt(x^2 +
/// y^2) >= 0: for a profile that stays in rho >= 0 the revolved distance is
/// exact, since the closest point lies in the same meridian half-plane.
///
/// Header-only and inline: the grid evaluates these millions of times.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace icrkit::sim::sdf {

using Eigen::Vector2d;
using Eigen::Vector3d;

// ---- CSG ------------------------------------------------------------------

inline double unite(double a, double b) { return std::min(a, b); }
inline double intersect(double a, double b) { return std::max(a, b); }
/// a without b.
inline double subtract(double a, double b) { return std::max(a, -b); }

/// Union with a fillet where the surfaces meet (polynomial smooth minimum):
/// the fillet spans where the two distances differ by less than `k` (metres)
/// and adds at most k/4 of material. Where both surfaces coincide it bulges
/// by k/4, so parts joined this way must cross, not touch.
inline double smoothUnite(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
/// a without b, the cut's edge rounded over about `k`.
inline double smoothSubtract(double a, double b, double k) { return -smoothUnite(-a, b, k); }

// ---- 2D profiles ----------------------------------------------------------

/// Axis-aligned box centred at the origin with half sizes `half`.
inline double box2(const Vector2d& p, const Vector2d& half) {
  const Vector2d d = p.cwiseAbs() - half;
  return d.cwiseMax(0.0).norm() + std::min(std::max(d.x(), d.y()), 0.0);
}
/// The same box with its corners rounded to `radius` (<= the half sizes).
inline double roundBox2(const Vector2d& p, const Vector2d& half, double radius) {
  return box2(p, half - Vector2d::Constant(radius)) - radius;
}
inline double circle2(const Vector2d& p, const Vector2d& centre, double radius) { return (p - centre).norm() - radius; }
/// Segment a-b thickened by `radius` (round ends).
inline double capsule2(const Vector2d& p, const Vector2d& a, const Vector2d& b, double radius) {
  const Vector2d pa = p - a, ba = b - a;
  const double t = std::clamp(pa.dot(ba) / ba.squaredNorm(), 0.0, 1.0);
  return (pa - t * ba).norm() - radius;
}
/// Isosceles trapezoid symmetric about x = 0: half width r1 at y = -he,
/// r2 at y = +he.
inline double trapezoid2(const Vector2d& p, double r1, double r2, double he) {
  const Vector2d k1(r2, he), k2(r2 - r1, 2.0 * he);
  const Vector2d q(std::abs(p.x()), p.y());
  const Vector2d ca(q.x() - std::min(q.x(), q.y() < 0.0 ? r1 : r2), std::abs(q.y()) - he);
  const Vector2d cb = q - k1 + k2 * std::clamp((k1 - q).dot(k2) / k2.squaredNorm(), 0.0, 1.0);
  const double s = (cb.x() < 0.0 && ca.y() < 0.0) ? -1.0 : 1.0;
  return s * std::sqrt(std::min(ca.squaredNorm(), cb.squaredNorm()));
}

/// (rho, z) of a point, for solids of revolution about the z axis.
inline Vector2d meridian(const Vector3d& p) { return {std::hypot(p.x(), p.y()), p.z()}; }

// ---- 3D solids ------------------------------------------------------------

inline double sphere(const Vector3d& p, const Vector3d& centre, double radius) { return (p - centre).norm() - radius; }

/// Axis-aligned box given by its corners.
inline double box(const Vector3d& p, const Vector3d& lo, const Vector3d& hi) {
  const Vector3d d = (p - 0.5 * (lo + hi)).cwiseAbs() - 0.5 * (hi - lo);
  return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
}

/// Capped cylinder along the coordinate axis `axis` (0 = x, 1 = y, 2 = z):
/// `radius` about the line through `centre`, between the coordinates `from`
/// and `to` (either order) along the axis.
inline double cylinder(const Vector3d& p, int axis, const Vector3d& centre, double radius, double from, double to) {
  Vector3d q = p - centre;
  const double along = p[axis] - 0.5 * (from + to);
  q[axis] = 0.0;
  return box2(Vector2d(q.norm(), along), Vector2d(radius, 0.5 * std::abs(to - from)));
}

/// Cone frustum from `a` (radius ra) to `b` (radius rb), flat caps.
inline double cappedCone(const Vector3d& p, const Vector3d& a, const Vector3d& b, double ra, double rb) {
  const double rba = rb - ra;
  const double baba = (b - a).squaredNorm();
  const double papa = (p - a).squaredNorm();
  const double paba = (p - a).dot(b - a) / baba;
  const double x = std::sqrt(std::max(papa - paba * paba * baba, 0.0));
  const double cax = std::max(0.0, x - (paba < 0.5 ? ra : rb));
  const double cay = std::abs(paba - 0.5) - 0.5;
  const double k = rba * rba + baba;
  const double f = std::clamp((rba * (x - ra) + paba * baba) / k, 0.0, 1.0);
  const double cbx = x - ra - f * rba;
  const double cby = paba - f;
  const double s = (cbx < 0.0 && cay < 0.0) ? -1.0 : 1.0;
  return s * std::sqrt(std::min(cax * cax + cay * cay * baba, cbx * cbx + cby * cby * baba));
}

/// Ring of elliptic cross-section in the x-z plane (a mug's handle): centre
/// line a circle of radius `ring_radius` about `centre`; the section has the
/// semi-axis `in_plane` across the ring (in x-z) and `across` along y.
/// Not an exact distance for an ellipse (the sign and zero set are exact).
inline double ellipticRingXZ(const Vector3d& p, const Vector3d& centre, double ring_radius, double in_plane,
                             double across) {
  const Vector3d q = p - centre;
  const double u = std::hypot(q.x(), q.z()) - ring_radius;
  const double v = q.y();
  return (std::hypot(u / in_plane, v / across) - 1.0) * std::min(in_plane, across);
}

}  // namespace icrkit::sim::sdf
