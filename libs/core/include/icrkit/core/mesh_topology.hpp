#pragma once
/// \file
/// Connectivity of a TriangleMesh: vertex neighbours, edges, components, areas.

#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace icrkit {

/// Vertex -> neighbouring vertices (those sharing a triangle edge), in
/// compressed rows; each row is sorted ascending and has no duplicates.
struct VertexAdjacency {
  std::vector<std::size_t> offsets;  ///< size vertexCount + 1
  std::vector<int> neighbours;

  std::size_t degree(std::size_t v) const { return offsets[v + 1] - offsets[v]; }
  const int* begin(std::size_t v) const { return neighbours.data() + offsets[v]; }
  const int* end(std::size_t v) const { return neighbours.data() + offsets[v + 1]; }
};

VertexAdjacency vertexAdjacency(const TriangleMesh& mesh);

/// Per vertex: 1 when some face uses it, 0 for an unreferenced vertex (a
/// point a reconstruction left unmeshed, such as the 1,113 strays of the
/// Stanford bunny's bun_zipper.ply).
/// Such a vertex is not on the surface: grasps, regions and mappings ignore
/// it, yet it keeps its index so that per-vertex attributes and the user's
/// indices keep their meaning. Compute it once per mesh and share it.
std::vector<std::uint8_t> referencedVertices(const TriangleMesh& mesh);

/// The positions of the vertices some face uses, in index order (all of them
/// for a mesh without unreferenced vertices): what a frame, a centroid or a
/// bounding sphere of the surface should be taken over.
std::vector<Eigen::Vector3d> referencedPositions(const TriangleMesh& mesh);

/// Vertex -> the faces that use it, in compressed rows; each row ascending
/// (a face that repeats a vertex is listed once per use).
struct VertexFaces {
  std::vector<std::size_t> offsets;  ///< size vertexCount + 1
  std::vector<int> faces;

  const int* begin(std::size_t v) const { return faces.data() + offsets[v]; }
  const int* end(std::size_t v) const { return faces.data() + offsets[v + 1]; }
};

VertexFaces vertexFaces(const TriangleMesh& mesh);

/// Area of every face (m^2); degenerate faces have area 0.
std::vector<double> faceAreas(const TriangleMesh& mesh);
double surfaceArea(const TriangleMesh& mesh);

struct EdgeStatistics {
  std::size_t edges = 0;               ///< distinct undirected edges
  std::size_t boundary_edges = 0;      ///< used by exactly one face
  std::size_t non_manifold_edges = 0;  ///< used by three or more faces
  /// Edges used by exactly two faces that both traverse it the same way
  /// (0 for a consistently oriented mesh).
  std::size_t misoriented_edges = 0;
};
EdgeStatistics edgeStatistics(const TriangleMesh& mesh);

/// Per vertex: 1 when it lies on an edge that only one face uses (the rim of
/// a hole or of the seen surface), else 0.
std::vector<std::uint8_t> boundaryVertices(const TriangleMesh& mesh);

/// Closed chains of boundary edges (edges used by one face), each as its
/// vertex sequence in the winding of the faces it borders. A vertex where
/// several holes touch appears in each of their loops. In a mesh that is not
/// consistently oriented a chain may stop short; it still counts as a loop.
std::vector<std::vector<int>> boundaryLoops(const TriangleMesh& mesh);
/// The same from the boundary half-edges (from, to) alone, for code that
/// already knows them.
std::vector<std::vector<int>> traceBoundaryLoops(std::vector<std::pair<int, int>> half_edges);

/// Connected components of the faces (two faces touch when they share a vertex).
struct MeshComponents {
  std::size_t count = 0;            ///< components that hold at least one face
  std::vector<int> face_component;  ///< per face, 0..count-1
  std::size_t unreferenced_vertices = 0;  ///< vertices used by no face
};
MeshComponents meshComponents(const TriangleMesh& mesh);

}  // namespace icrkit
