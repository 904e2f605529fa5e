#pragma once
/// \file
/// Triangulates the zero level set of a scalar field (a signed distance
/// function, negative inside) sampled on a regular grid: marching cubes in
/// which each cube's polygons are the loops traced on its faces, so that
/// the result is a closed, edge- and vertex-manifold, consistently oriented
/// surface whatever the field (internal to icrkit::sim).
///
/// - Vertices sit on the grid edges whose end nodes differ in sign (a node
///   with value 0 counts as outside), one per edge, shared by the four cubes
///   around it. Each is placed on the zero level set by a bracketed root
///   search along its edge (Illinois false position), not by linear
///   interpolation, then kept 1 % of a cell away from the nodes so that no
///   face degenerates.
/// - On each cube face the crossings are joined by segments that separate
///   the inside nodes from the outside ones. A face with four crossings
///   (diagonal nodes alike) is decided by the asymptotic decider: the sign of
///   the bilinear interpolant at its saddle point. That decision depends only
///   on the face's four values, so the two cubes sharing the face agree and
///   no cracks open between cubes.
/// - The segments of a cube link up into closed loops, each bounding one
///   disc of surface. A loop of three is one triangle; a longer loop is fanned
///   from one of its vertices when none of the fan's diagonals joins two grid
///   edges of a common cube face (such a diagonal could also be made by the
///   neighbouring cube, giving an edge with four faces); otherwise a vertex
///   is added at the loop's centroid, moved onto the level set by Newton
///   steps, and the loop is fanned from it.
/// - Faces are wound counter-clockwise seen from outside (positive values).
///
/// The surface is closed only when the field is positive on every boundary
/// node of the grid (checked). Deterministic: the field is sampled in
/// parallel, but every value, vertex and face is the same for any thread
/// count and in the same order.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <functional>

namespace icrkit::sim {

/// Scalar field over space (metres in, metres out), negative inside.
using ScalarField = std::function<double(const Eigen::Vector3d&)>;

/// Sample nodes origin + cell * (i, j, k), 0 <= i < nodes.x() and so on.
struct SampleGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double cell = 0.0;                                 ///< metres
  Eigen::Vector3i nodes = Eigen::Vector3i::Zero();  ///< per axis, >= 2

  Eigen::Vector3d node(int i, int j, int k) const { return origin + cell * Eigen::Vector3d(i, j, k); }
};

/// The smallest grid with cell size `cell` that has a node at `anchor` (not
/// necessarily inside the grid) and holds `bounds` with `margin_cells` of
/// nodes to spare on every side.
SampleGrid gridAround(const Eigen::AlignedBox3d& bounds, double cell, const Eigen::Vector3d& anchor,
                      int margin_cells = 2);

struct ImplicitMeshStatistics {
  std::size_t edge_vertices = 0;    ///< vertices on grid edges
  std::size_t centre_vertices = 0;  ///< vertices added inside loops that could not be fanned
  std::size_t loops = 0;            ///< polygons traced, one per surface piece in a cube
};

/// The level set field = 0 of `field` on `grid`. Throws std::invalid_argument
/// for a grid with fewer than 2 nodes on an axis, a cell size <= 0, a
/// non-finite sample, or a negative sample on the grid boundary.
TriangleMesh meshImplicitSurface(const ScalarField& field, const SampleGrid& grid,
                                 ImplicitMeshStatistics* statistics = nullptr);

}  // namespace icrkit::sim
