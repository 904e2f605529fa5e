#pragma once
/// \file
/// Ray casting and closest-point queries against a TriangleMesh with Embree 3.
///
/// One Embree device is shared by the whole process; each RayCaster owns a
/// committed scene. All queries are const and may run concurrently.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace icrkit {

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  ///< need not be unit length
  double t_min = 0.0;  ///< metres along the normalised direction; closer hits are ignored
  double t_max = std::numeric_limits<double>::infinity();
};

struct RayHit {
  bool hit = false;
  double distance = std::numeric_limits<double>::infinity();  ///< along the ray, metres
  int face = -1;
  double u = 0.0, v = 0.0;  ///< barycentrics: point = (1-u-v) a + u b + v c
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d face_normal = Eigen::Vector3d::Zero();  ///< unit, from the face winding
};

struct ClosestPoint {
  bool found = false;
  double distance = std::numeric_limits<double>::infinity();  ///< from the query, metres
  int face = -1;
  double u = 0.0, v = 0.0;  ///< barycentrics: point = (1-u-v) a + u b + v c
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d face_normal = Eigen::Vector3d::Zero();  ///< unit, from the face winding; zero if degenerate
};

/// Optional per-face mask: when non-empty (one entry per face), only faces
/// with a non-zero entry can be hit.
using FaceMask = std::vector<std::uint8_t>;

class RayCaster {
public:
  /// Builds the acceleration structure (single precision, like every Embree
  /// scene) and keeps a double-precision copy of the face vertices for the
  /// closest-point queries. Throws std::invalid_argument for an invalid mesh.
  explicit RayCaster(const TriangleMesh& mesh);
  ~RayCaster();
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;

  std::size_t faceCount() const;

  /// Closest hit along `ray` with distance in [t_min, t_max], measured in
  /// metres along the normalised direction.
  RayHit closestHit(const Ray& ray, const FaceMask& mask = {}) const;

  /// Every hit on the full line through `origin` along `direction`, both
  /// ways: signed distances (negative behind the origin), sorted ascending.
  /// A line through a shared edge or vertex reports each face it touches.
  std::vector<RayHit> allHitsOnLine(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                    const FaceMask& mask = {}) const;

  /// Closest hits for many rays, in parallel (TBB); result[i] is for rays[i].
  std::vector<RayHit> closestHits(const std::vector<Ray>& rays, const FaceMask& mask = {}) const;
  /// allHitsOnLine for many lines, in parallel.
  std::vector<std::vector<RayHit>> allHitsOnLines(const std::vector<Eigen::Vector3d>& origins,
                                                  const std::vector<Eigen::Vector3d>& directions,
                                                  const FaceMask& mask = {}) const;

  /// The point of the surface closest to `query`, if one lies within
  /// `max_distance` metres (inclusive). Embree only prunes the search; every
  /// candidate face is measured in double precision from the mesh's own
  /// vertices (closestPointOnTriangle), so the answer is as exact as double
  /// arithmetic allows, with no float rounding. Among equally distant faces
  /// the lowest index wins. A non-finite query finds nothing. Throws
  /// std::invalid_argument for a negative or NaN `max_distance`, or a mask
  /// of the wrong size.
  ClosestPoint closestPoint(const Eigen::Vector3d& query,
                            double max_distance = std::numeric_limits<double>::infinity(),
                            const FaceMask& mask = {}) const;

  /// closestPoint for many queries, in parallel (TBB); result[i] is for
  /// queries[i] and equals closestPoint(queries[i], ...). Answered in a
  /// spatial order of the queries, which keeps face data in cache: sorting
  /// the queries beforehand gains nothing.
  std::vector<ClosestPoint> closestPoints(const std::vector<Eigen::Vector3d>& queries,
                                          double max_distance = std::numeric_limits<double>::infinity(),
                                          const FaceMask& mask = {}) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace icrkit
