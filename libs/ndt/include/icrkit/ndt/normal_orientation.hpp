#pragma once
/// \file
/// Consistent orientation of estimated point normals.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>

namespace icrkit::ndt {

struct NormalOrientationParameters {
  std::size_t neighbours = 8;  ///< k of the k-nearest-neighbour graph used for propagation
};

/// Flips the cloud's normals (zero normals are left alone):
/// - with a viewpoint: each normal towards it (a single range view);
/// - without: outwards from the centroid for the most clearly outward point
///   of each connected part of the k-NN graph, then propagated along a
///   minimum spanning tree weighted by 1 - |n_i . n_j| (Hoppe et al. 1992),
///   so that neighbours agree. Deterministic (ties by index).
/// Returns the number of normals flipped.
std::size_t orientNormals(PointCloud& cloud, const std::optional<Eigen::Vector3d>& viewpoint,
                          const NormalOrientationParameters& params = {});

}  // namespace icrkit::ndt
