#pragma once
/// \file
/// Point normals from the same local Gaussian fit as the smoothing layer:
/// the normal is the eigenvector of the smallest eigenvalue (v3) of the
/// covariance of the points within a radius, oriented consistently.

#include <icrkit/core/length.hpp>
#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace icrkit::ndt {

struct NormalEstimationParameters {
  /// Window radius: metres, or a multiple of the median nearest-neighbour
  /// spacing (default 3 spacings). Finite and > 0.
  Length radius = Length::spacings(3.0);
  /// A window with fewer points than this uses the k nearest points
  /// instead (k = min_neighbours), so isolated points still get a normal.
  std::size_t min_neighbours = 8;
  /// Orientation: towards this sensor position when given, else outwards
  /// and consistent over the neighbour graph (see orientNormals).
  std::optional<Eigen::Vector3d> viewpoint;
  /// Per point: each normal faces its own sensor position (a cloud fused
  /// from several views). When non-empty it must hold one entry per point
  /// and takes precedence over `viewpoint`.
  std::vector<Eigen::Vector3d> viewpoints;
  /// Sum each window over its points in ascending index (one k-d tree
  /// query per point) instead of cube by cube (RadiusCells: 2-3x faster on
  /// a dense fused cloud). Both are deterministic whatever the thread
  /// count and differ only in the last bits of the sums. The registration
  /// keeps index order: on rotationally symmetric objects its outcome can
  /// turn on such bits (docs/performance.md, stop 45).
  bool index_order = false;
};

struct NormalEstimationReport {
  std::size_t points = 0;
  double radius_m = 0.0;
  std::size_t small_windows = 0;  ///< points that fell back to the k nearest
  std::size_t flipped = 0;        ///< normals turned by the orientation step
};

/// Replaces the cloud's normals by estimated unit normals and adds their
/// uncertainty as the attributes `normal_sigma` (float, radians) and
/// `position_sigma` (float, metres: the point's own noise along the normal,
/// since it is not moved; fit_uncertainty.hpp). Throws InputError
/// for fewer than 3 points, a non-finite coordinate (naming the point) or a
/// radius that is not positive. Parallel and deterministic.
NormalEstimationReport estimateNormals(PointCloud& cloud, const NormalEstimationParameters& params = {});

}  // namespace icrkit::ndt
