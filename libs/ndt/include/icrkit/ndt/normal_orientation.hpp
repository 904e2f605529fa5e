#pragma once
/// \file
/// Consistent orientation of estimated point normals.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace icrkit::ndt {

struct NormalOrientationParameters {
  std::size_t neighbours = 8;  ///< k of the k-nearest-neighbour graph used for propagation
};

/// Up to `slots` neighbours per point: neighbours[i * slots + s]; an unused
/// slot holds the point count.
struct NeighbourGraph {
  std::size_t slots = 0;
  std::vector<std::size_t> neighbours;
};

/// Each point's k nearest other points (ties by index), computed in parallel.
NeighbourGraph nearestNeighbourGraph(const std::vector<Eigen::Vector3d>& points, std::size_t k);

/// Flips the cloud's normals (zero normals are left alone):
/// - with a viewpoint: each normal towards it (a single range view);
/// - without: along a maximum spanning forest of the k-NN graph weighted by
///   |n_i . n_j| (Hoppe et al. 1992), so that neighbours agree, each tree
///   rooted at its most clearly outward point (normal most nearly along the
///   direction from the centroid), which is turned outwards.
/// Deterministic whatever the thread count. Returns the number flipped.
std::size_t orientNormals(PointCloud& cloud, const std::optional<Eigen::Vector3d>& viewpoint,
                          const NormalOrientationParameters& params = {});

/// The same without a viewpoint, over a neighbour graph the caller already
/// has (the smoothing pass keeps the nearest points of each window).
std::size_t orientNormalsOverGraph(PointCloud& cloud, const NeighbourGraph& graph);

}  // namespace icrkit::ndt
