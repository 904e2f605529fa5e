#pragma once
/// \file
/// Meshes of simple shapes, for tests, benchmarks and examples.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

namespace icrkit {

/// A geodesic sphere: an icosahedron whose faces are split in four
/// `subdivisions` times, every new vertex pushed onto the sphere. Near-uniform
/// vertex spacing (unlike a UV sphere's crowded poles); 10 * 4^s + 2
/// vertices, 20 * 4^s faces wound outwards, exact outward unit normals.
/// Throws std::invalid_argument for subdivisions outside 0..9 or a radius <= 0.
TriangleMesh makeIcosphere(int subdivisions, double radius = 1.0,
                           const Eigen::Vector3d& centre = Eigen::Vector3d::Zero());

}  // namespace icrkit
