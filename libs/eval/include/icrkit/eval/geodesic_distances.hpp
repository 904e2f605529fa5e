#pragma once
/// \file
/// Distances between vertices of one triangle mesh (the CAD mesh of the
/// Fig. 7 quality criterion): geodesic along the surface, or straight-line.
///
/// Geodesics are exact shortest paths in a graph over the vertices
/// (Dijkstra): by default the mesh edges, each weighted by its Euclidean
/// length. A path along edges is a path on the surface, so this never
/// underestimates the surface geodesic, but it overestimates it wherever the
/// straight surface line crosses triangles instead of following edges.
/// Measured against exact great-circle / planar distances
/// (MeshDistances.SphereOverestimateIsBounded and
/// .FlatGridOverestimateAgainstPlanarDistance, pairs >= 5 mean edge lengths
/// apart; relative overestimate mean / 95th percentile / max):
///   - icosphere, 10,242 vertices:   7.4 % / 14.2 % / 23.1 %  (>= 20 edges apart: 7.0 / 12.8 / 17.6 %)
///   - UV sphere 64 x 128:           5.7 % / 22.4 % / 40.5 %
///   - flat grid, squares split along one diagonal: mean 17.4 %, max 41.4 %
///     (sqrt 2 - 1: exact along the axes and that diagonal, Manhattan across it)
/// With GeodesicPaths::EdgesAndUnfoldedDiagonals:
///   - icosphere 1.5 % / 3.1 % / 5.0 %; UV sphere 1.6 % / 5.0 % / 12.2 %;
///     flat grid mean 3.3 %, max 8.2 %;
/// for ~1.5x the graph size and build time. Both graphs' metrics are
/// anisotropic on regular meshes, which can create ties (see centralPoint).
///
/// Thread safety: a MeshDistanceGraph is immutable once built and may be
/// shared by any number of threads; each thread brings its own
/// DistanceWorkspace. Every answer is deterministic: equal distances are
/// broken by the lower vertex index.

#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace icrkit::eval {

enum class DistanceMetric {
  Geodesic,  ///< shortest path over the mesh surface, as approximated by the graph (GeodesicPaths)
  Euclidean  ///< straight line through space, ignoring the surface
};

/// Which surface paths the geodesic search may take.
enum class GeodesicPaths {
  /// Mesh edges only: overestimates the surface geodesic by ~7 % on average,
  /// up to ~20 % on near-equilateral meshes and 41 % on regular grids (see above).
  Edges,
  /// Edges plus, for every interior edge whose two triangles form a convex
  /// quadrilateral when unfolded into a plane, the straight line between the
  /// two opposite vertices across both triangles (its unfolded length). Still
  /// a real surface path, so still never below the true geodesic.
  EdgesAndUnfoldedDiagonals
};

struct MeshDistanceGraphParameters {
  GeodesicPaths paths = GeodesicPaths::Edges;
};

/// A vertex and its distance from a query's source; vertex -1 and an
/// infinite distance when nothing was reachable.
struct NearestVertex {
  int vertex = -1;
  double distance = std::numeric_limits<double>::infinity();  ///< metres
};

class MeshDistanceGraph;

/// Scratch memory for distance queries, sized to the mesh on first use and
/// then reused without O(V) work per query (arrays are invalidated by
/// bumping an epoch counter, not cleared). One per thread; it may serve
/// several graphs in turn.
class DistanceWorkspace {
public:
  DistanceWorkspace() = default;

  /// Vertices settled by Dijkstra since construction: a cost measure for
  /// tests and benchmarks.
  std::uint64_t settledVertices() const { return settled_total_; }

private:
  friend class MeshDistanceGraph;

  void prepare(std::size_t vertex_count);
  std::uint32_t nextVisitEpoch();
  std::uint32_t nextTargetEpoch();

  std::vector<double> distance_;
  std::vector<std::uint32_t> visited_;  ///< == visit_epoch_: distance_ is valid in this query
  std::vector<std::uint32_t> target_;   ///< == target_epoch_: a target of this query
  std::uint32_t visit_epoch_ = 0;
  std::uint32_t target_epoch_ = 0;
  std::vector<std::pair<double, int>> heap_;  ///< min-heap with lazy deletion
  std::uint64_t settled_total_ = 0;
};

/// The mesh prepared for distance queries: adjacency with edge lengths,
/// mesh-boundary flags and connected components. Keeps a reference to the
/// mesh, which must outlive it and not change.
class MeshDistanceGraph {
public:
  /// Throws InputError("mesh", ...) when the mesh is invalid.
  explicit MeshDistanceGraph(const TriangleMesh& mesh, const MeshDistanceGraphParameters& params = {});

  const TriangleMesh& mesh() const { return *mesh_; }
  const VertexAdjacency& adjacency() const { return adjacency_; }
  const MeshDistanceGraphParameters& parameters() const { return params_; }
  std::size_t vertexCount() const { return adjacency_.offsets.size() - 1; }
  const Eigen::Vector3d& position(int v) const { return mesh_->vertices.positions[static_cast<std::size_t>(v)]; }

  /// On an edge used by exactly one face, or used by no face at all: where
  /// the surface ends.
  bool onMeshBoundary(int v) const { return boundary_[static_cast<std::size_t>(v)] != 0; }
  /// Connected component of the edge graph, numbered 0.. in order of each
  /// component's lowest vertex; a vertex used by no face is its own component.
  int component(int v) const { return component_[static_cast<std::size_t>(v)]; }
  std::size_t componentCount() const { return component_count_; }

  /// Distance from `source` to each of `targets`, in their order (duplicates
  /// allowed); +infinity for a target in another component. A geodesic query
  /// stops as soon as every target is settled.
  /// Throws InputError("vertex index", ...) for an index out of range.
  std::vector<double> distances(int source, const std::vector<int>& targets, DistanceMetric metric,
                                DistanceWorkspace& workspace) const;

  /// The target closest to `source` (itself, at 0, when it is a target); a
  /// geodesic query stops at the first target settled. Equal distances: the
  /// lower index. Empty or unreachable targets: vertex -1, infinite distance.
  NearestVertex nearest(int source, const std::vector<int>& targets, DistanceMetric metric,
                        DistanceWorkspace& workspace) const;

  /// Largest distance from `source` to `targets` (0 for no targets;
  /// +infinity when one is unreachable). The search gives up and returns
  /// +infinity as soon as the answer is known to exceed `give_up_above`,
  /// which bounds a geodesic search to that radius (and, A*-like, to the
  /// vertices that could still reach the targets' bounding box within it).
  double eccentricity(int source, const std::vector<int>& targets, DistanceMetric metric,
                      DistanceWorkspace& workspace,
                      double give_up_above = std::numeric_limits<double>::infinity()) const;

  /// Shortest (graph) paths from `source` to every vertex within
  /// `max_distance` (metres); the others stay +infinity. For renders and
  /// tests; costs O(V) for the returned array.
  std::vector<double> geodesicField(int source, DistanceWorkspace& workspace,
                                    double max_distance = std::numeric_limits<double>::infinity()) const;

private:
  // Settles vertices from `source` in order of distance and calls
  // on_settle(vertex, distance) for each, which returns false to stop.
  template <typename OnSettle>
  void dijkstra(int source, DistanceWorkspace& workspace, double radius, OnSettle&& on_settle) const;
  // The same, skipping any vertex w reached at distance dw for which
  // prune(w, dw) holds.
  template <typename OnSettle, typename Prune>
  void dijkstra(int source, DistanceWorkspace& workspace, double radius, OnSettle&& on_settle, Prune&& prune) const;
  void checkIndex(int v) const;
  void markTargets(const std::vector<int>& targets, DistanceWorkspace& workspace, std::size_t& distinct) const;

  const TriangleMesh* mesh_;
  MeshDistanceGraphParameters params_;
  VertexAdjacency adjacency_;
  // Search neighbours in compressed rows: the mesh edges, plus the unfolded
  // diagonals when requested, each with its length.
  std::vector<std::size_t> link_offsets_;
  std::vector<int> link_target_;
  std::vector<double> link_length_;
  std::vector<std::uint8_t> boundary_;
  std::vector<int> component_;
  std::size_t component_count_ = 0;
};

}  // namespace icrkit::eval
