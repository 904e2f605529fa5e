#pragma once
/// \file
/// Random points on the surface of a TriangleMesh.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <cstdint>

namespace icrkit {

/// `count` points drawn independently and uniformly over the surface area
/// (a face is picked with probability proportional to its area, then a
/// uniform point inside it), with unit normals: the barycentric blend of
/// the vertex normals when the mesh has them (the face normal where the
/// blend vanishes), else the face normal from the winding. No colours or
/// attributes. The same for a seed whatever the thread count.
/// Throws std::invalid_argument for an invalid mesh, or for count > 0 on a
/// mesh without area (no faces, or only degenerate ones).
PointCloud samplePointsUniformly(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed = 1);

/// A Poisson-disk sample: no two points closer than `min_distance` (metres),
/// and the surface covered so that hardly a gap of 2 x `min_distance`
/// remains (median nearest-neighbour distance about 1.1 x `min_distance`).
/// Dart throwing over a uniform sample `oversampling` times as dense as the
/// result can be: candidates are taken in their (random) order and kept
/// when no kept point is within `min_distance`. Normals as in
/// samplePointsUniformly. The same for a seed whatever the thread count.
/// Throws std::invalid_argument for min_distance <= 0 or a mesh without area.
PointCloud samplePointsPoissonDisk(const TriangleMesh& mesh, double min_distance, std::uint64_t seed = 1,
                                   double oversampling = 6.0);

}  // namespace icrkit
