#pragma once
/// \file
/// Distances between two triangle-mesh surfaces: one-sided statistics and
/// the (sampled) Hausdorff distance, e.g. to compare a reconstruction with
/// its ground truth.

#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <cstdint>

namespace icrkit {

struct MeshDistanceParameters {
  /// Area-weighted random points on the faces of the measured mesh, on top
  /// of its vertices; more find the largest gap more reliably.
  std::size_t samples = 100000;
  std::uint64_t seed = 1;  ///< for the face samples (samplePointsUniformly)
};

struct MeshDistanceStatistics {
  std::size_t points = 0;  ///< points measured: every vertex of `from`, then the face samples
  double max = 0.0;        ///< metres
  double mean = 0.0;
  double rms = 0.0;
  double median = 0.0;     ///< the mean of the two middle values for an even count
};

/// One-sided distances from the surface of `from` to the surface of `to`:
/// for every vertex of `from` (including any used by no face, so a mesh
/// without faces measures a point cloud) and `params.samples` uniform random
/// points on its faces, the exact distance to the closest point of `to`
/// (RayCaster::closestPoint). Deterministic for a seed whatever the thread
/// count. Not symmetric: a part of `to` that `from` lacks does not show up.
/// Throws std::invalid_argument when either mesh is invalid, `from` has no
/// vertices or `to` has no faces.
MeshDistanceStatistics meshDistance(const TriangleMesh& from, const TriangleMesh& to,
                                    const MeshDistanceParameters& params = {});

/// The symmetric Hausdorff distance estimated from those samples: the larger
/// of the two one-sided maxima. A lower bound of the true value that
/// approaches it as the sample count grows.
double hausdorffDistance(const TriangleMesh& a, const TriangleMesh& b, const MeshDistanceParameters& params = {});

}  // namespace icrkit
