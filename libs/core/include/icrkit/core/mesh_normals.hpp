#pragma once
/// \file
/// Face winding repair and vertex normals.

#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>

namespace icrkit {

struct OrientationReport {
  std::size_t flipped_faces = 0;
  /// Edges over which no consistent winding exists (non-orientable surface
  /// or non-manifold edge); their faces keep the winding BFS gave them.
  std::size_t conflicting_edges = 0;
};

/// Makes the winding of neighbouring faces agree (each shared manifold edge
/// traversed in opposite directions), then turns every component outwards:
/// closed components by the sign of their enclosed volume, open ones
/// (single range views) so that the area-weighted normals point away from
/// the component's centroid on average.
OrientationReport orientFaces(TriangleMesh& mesh);

struct VertexNormalParameters {
  bool orient_faces = true;  ///< run orientFaces() first
};

/// Area-weighted vertex normals from the faces, unit length. A vertex no
/// face uses has no normal of its own; it borrows that of the nearest vertex
/// that has one (ties: the lower index), so that every written normal is a
/// unit vector and the file stays readable by tools that insist on that. The
/// borrowed normal carries no information: grasps, regions and mappings
/// ignore such vertices (referencedVertices()). A vertex used only by
/// degenerate faces gets (0, 0, 0), as does every vertex of a mesh whose
/// faces are all degenerate (or that has none).
OrientationReport computeVertexNormals(TriangleMesh& mesh, const VertexNormalParameters& params = {});

}  // namespace icrkit
