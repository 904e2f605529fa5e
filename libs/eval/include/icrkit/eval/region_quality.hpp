#pragma once
/// \file
/// The quality criterion Q_n = d2 / d1 of Fig. 7 (Krug et al.): how far the
/// central point of a region computed on a reconstructed mesh, mapped onto
/// the CAD mesh, lies inside the ground-truth CAD region C_n^C, relative to
/// how far the CAD region's own central point lies inside it.
///
/// Definitions, all on the CAD mesh (regions are sets of its vertex indices):
///   - border of C^C: its vertices with a mesh neighbour outside C^C, or on
///     the mesh's own boundary (an edge used by one face, or no face at all),
///     because the region, and a finger's freedom, ends there too. A
///     one-vertex region is therefore its own border.
///   - central point of a vertex set: the vertex of the set minimising its
///     largest distance to the set's other vertices; ties -> lowest index.
///     Distances are over the whole mesh, not only through the set.
///   - d1: distance from the CAD central point to the nearest border vertex
///     (0 when it is one).
///   - d2: distance from the mapped region's central point to the nearest
///     border vertex, positive when that point is in C^C, negative when not.
///   - Q_n = d2 / d1, left unset (not dropped: see RegionQuality::reason)
///     when d1 = 0.
/// With the geodesic metric, a set spread over several connected components
/// of the mesh has no finite eccentricity; its central point is then sought
/// in the component holding most of its vertices (ties: the one holding the
/// lowest index), the others are ignored and counted.

#include <icrkit/eval/geodesic_distances.hpp>

#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

struct RegionQualityParameters {
  DistanceMetric metric = DistanceMetric::Geodesic;
  /// For DistanceMetric::Geodesic: which surface paths approximate geodesics.
  GeodesicPaths paths = GeodesicPaths::Edges;
};

struct CentralPoint {
  int vertex = -1;              ///< -1 for an empty set
  double eccentricity_m = 0.0;  ///< its largest distance to the other vertices considered
  std::size_t vertices = 0;     ///< distinct vertices considered
  /// Distinct vertices ignored for lying in another mesh component than the
  /// one chosen (geodesic metric only).
  std::size_t ignored = 0;
  /// Candidates whose exact eccentricity had to be computed (one Dijkstra
  /// each for the geodesic metric): a cost measure.
  std::size_t evaluations = 0;
};

/// The central point of `vertices` (duplicates allowed); the same answer as
/// evaluating every vertex's eccentricity, bit for bit. Candidates are
/// visited in ascending order of a lower bound on their eccentricity
/// (Euclidean distances to a few extreme vertices, then all Euclidean
/// distances: straight lines are never longer than surface paths) and the
/// search stops when the bound exceeds the best eccentricity found; each
/// geodesic evaluation gives up beyond that best value. When that prunes
/// poorly (a region curved around a handle), batches of geodesic anchors
/// (full distance fields from farthest-point-sampled vertices) tighten the
/// bounds. Typical cost: 1-5 Dijkstras over the region; a band all the way
/// around a handle, where every vertex is nearly as central, needs O(k).
/// On regular meshes the graph metric is anisotropic and the centre can tie
/// with off-centre vertices (e.g. along the split diagonal of a grid): the
/// lowest index then wins, as the definition says.
/// Throws InputError("vertex index", ...) for an index out of range.
CentralPoint centralPoint(const MeshDistanceGraph& graph, const std::vector<int>& vertices, DistanceMetric metric,
                          DistanceWorkspace& workspace);

/// The border of `region` (duplicates allowed) as defined above, sorted
/// ascending. Throws InputError("vertex index", ...) for an index out of range.
std::vector<int> regionBorder(const MeshDistanceGraph& graph, const std::vector<int>& region);

/// The CAD side of Q_n, which does not depend on the reconstructed region:
/// compute it once per CAD region and reuse it for each mesh compared.
struct CadRegionSummary {
  std::vector<int> vertices;  ///< sorted, distinct
  std::vector<int> border;    ///< sorted
  CentralPoint center;
  double d1_m = 0.0;
};

struct RegionQuality {
  int cad_center = -1;
  int mapped_center = -1;            ///< -1 for an empty mapped region
  bool mapped_center_inside = false; ///< mapped_center is a vertex of C^C
  double d1_m = 0.0;
  double d2_m = 0.0;                 ///< negative when the mapped centre is outside C^C
  std::optional<double> quality;     ///< d2 / d1; unset when undefined, see `reason`
  /// Why `quality` is unset; empty when it is set. One of:
  /// "empty mapped region", "d1 = 0: the CAD central point is on the border",
  /// "mapped central point cannot reach the CAD region" (geodesic, other component),
  /// "the CAD region has no border: it covers a whole closed component" (d1 infinite).
  std::string reason;
  std::size_t cad_vertices = 0;      ///< distinct
  std::size_t cad_border_vertices = 0;
  std::size_t mapped_vertices = 0;   ///< distinct
  std::size_t mapped_ignored = 0;    ///< see CentralPoint::ignored
};

/// Q_n for many regions on one CAD mesh. Built once (adjacency, edge
/// lengths); `evaluate` is const and thread-safe given one DistanceWorkspace
/// per thread, and deterministic. Keeps a reference to the mesh, which must
/// outlive it.
class RegionQualityEvaluator {
public:
  /// Throws InputError("mesh", ...) for an invalid mesh.
  explicit RegionQualityEvaluator(const TriangleMesh& cad_mesh, const RegionQualityParameters& params = {});

  const MeshDistanceGraph& graph() const { return graph_; }
  const RegionQualityParameters& parameters() const { return params_; }

  /// Throws InputError("CAD region", ...) when `cad_region` is empty or holds
  /// an index out of range.
  CadRegionSummary summarize(const std::vector<int>& cad_region, DistanceWorkspace& workspace) const;

  /// `mapped_region`: the reconstructed region's vertices mapped onto the CAD
  /// mesh (eq. 3), duplicates allowed; an empty one gives quality unset with
  /// reason "empty mapped region". Throws InputError("mapped region", ...)
  /// for an index out of range.
  RegionQuality evaluate(const CadRegionSummary& cad, const std::vector<int>& mapped_region,
                         DistanceWorkspace& workspace) const;
  RegionQuality evaluate(const std::vector<int>& cad_region, const std::vector<int>& mapped_region,
                         DistanceWorkspace& workspace) const;

private:
  RegionQualityParameters params_;
  MeshDistanceGraph graph_;
};

}  // namespace icrkit::eval
