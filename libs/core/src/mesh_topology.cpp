#include <icrkit/core/mesh_topology.hpp>

#include <icrkit/core/disjoint_sets.hpp>

#include <algorithm>
#include <cstdint>
#include <utility>

namespace icrkit {
namespace {

// One face's use of an undirected edge (a < b); `forward` when the face runs
// it from a to b.
struct FaceEdge {
  int a, b;
  bool forward;
  bool operator<(const FaceEdge& o) const {
    return a != o.a ? a < o.a : b != o.b ? b < o.b : forward < o.forward;
  }
};

// Each undirected edge once per face that uses it, sorted, so that equal
// edges are adjacent and their multiplicity is a run length.
std::vector<FaceEdge> sortedFaceEdges(const TriangleMesh& mesh) {
  std::vector<FaceEdge> edges;
  edges.reserve(mesh.faces.size() * 3);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (a != b) edges.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  std::sort(edges.begin(), edges.end());
  return edges;
}


}  // namespace

VertexAdjacency vertexAdjacency(const TriangleMesh& mesh) {
  const std::size_t n = mesh.vertexCount();
  std::vector<std::pair<int, int>> directed;
  directed.reserve(mesh.faces.size() * 6);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (a == b) continue;
      directed.emplace_back(a, b);
      directed.emplace_back(b, a);
    }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());

  VertexAdjacency adjacency;
  adjacency.offsets.assign(n + 1, 0);
  for (const auto& e : directed) ++adjacency.offsets[static_cast<std::size_t>(e.first) + 1];
  std::partial_sum(adjacency.offsets.begin(), adjacency.offsets.end(), adjacency.offsets.begin());
  adjacency.neighbours.reserve(directed.size());
  for (const auto& e : directed) adjacency.neighbours.push_back(e.second);
  return adjacency;
}

std::vector<std::uint8_t> referencedVertices(const TriangleMesh& mesh) {
  std::vector<std::uint8_t> used(mesh.vertexCount(), 0);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(f[k])] = 1;
  return used;
}

std::vector<Eigen::Vector3d> referencedPositions(const TriangleMesh& mesh) {
  const std::vector<std::uint8_t> used = referencedVertices(mesh);
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(mesh.vertexCount());
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) positions.push_back(mesh.vertices.positions[v]);
  return positions;
}

VertexFaces vertexFaces(const TriangleMesh& mesh) {
  VertexFaces incidence;
  incidence.offsets.assign(mesh.vertexCount() + 1, 0);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) ++incidence.offsets[static_cast<std::size_t>(f[k]) + 1];
  std::partial_sum(incidence.offsets.begin(), incidence.offsets.end(), incidence.offsets.begin());
  incidence.faces.resize(incidence.offsets.back());
  std::vector<std::size_t> next(incidence.offsets.begin(), incidence.offsets.end() - 1);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) incidence.faces[next[static_cast<std::size_t>(mesh.faces[i][k])]++] = static_cast<int>(i);
  return incidence;
}

std::vector<double> faceAreas(const TriangleMesh& mesh) {
  std::vector<double> areas(mesh.faces.size());
  const auto& p = mesh.vertices.positions;
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const Triangle& f = mesh.faces[i];
    areas[i] = 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
  }
  return areas;
}

double surfaceArea(const TriangleMesh& mesh) {
  const std::vector<double> areas = faceAreas(mesh);
  return std::accumulate(areas.begin(), areas.end(), 0.0);
}

std::vector<std::uint8_t> boundaryVertices(const TriangleMesh& mesh) {
  std::vector<std::uint8_t> boundary(mesh.vertexCount(), 0);
  const auto edges = sortedFaceEdges(mesh);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i == 1) boundary[static_cast<std::size_t>(edges[i].a)] = boundary[static_cast<std::size_t>(edges[i].b)] = 1;
    i = j;
  }
  return boundary;
}

EdgeStatistics edgeStatistics(const TriangleMesh& mesh) {
  const auto edges = sortedFaceEdges(mesh);
  EdgeStatistics stats;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    const std::size_t uses = j - i;
    ++stats.edges;
    if (uses == 1) ++stats.boundary_edges;
    if (uses == 2 && edges[i].forward == edges[i + 1].forward) ++stats.misoriented_edges;
    if (uses >= 3) ++stats.non_manifold_edges;
    i = j;
  }
  return stats;
}

std::vector<std::vector<int>> traceBoundaryLoops(std::vector<std::pair<int, int>> half_edges) {
  std::sort(half_edges.begin(), half_edges.end());
  std::vector<std::uint8_t> taken(half_edges.size(), 0);
  auto takeFrom = [&](int v) -> long {
    auto it = std::lower_bound(half_edges.begin(), half_edges.end(), std::make_pair(v, -1));
    for (; it != half_edges.end() && it->first == v; ++it) {
      const auto k = static_cast<std::size_t>(it - half_edges.begin());
      if (!taken[k]) {
        taken[k] = 1;
        return static_cast<long>(k);
      }
    }
    return -1;
  };
  std::vector<std::vector<int>> loops;
  for (std::size_t start = 0; start < half_edges.size(); ++start) {
    if (taken[start]) continue;
    taken[start] = 1;
    std::vector<int> loop{half_edges[start].first};
    int v = half_edges[start].second;
    while (v != half_edges[start].first) {
      loop.push_back(v);
      const long next = takeFrom(v);
      if (next < 0) break;
      v = half_edges[static_cast<std::size_t>(next)].second;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<std::vector<int>> boundaryLoops(const TriangleMesh& mesh) {
  const auto edges = sortedFaceEdges(mesh);
  // Boundary half-edges in the direction their face runs them, grouped by
  // start vertex so that a loop can be followed head to tail.
  std::vector<std::pair<int, int>> half_edges;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i == 1)
      half_edges.push_back(edges[i].forward ? std::make_pair(edges[i].a, edges[i].b)
                                            : std::make_pair(edges[i].b, edges[i].a));
    i = j;
  }
  return traceBoundaryLoops(std::move(half_edges));
}

MeshComponents meshComponents(const TriangleMesh& mesh) {
  const std::size_t n = mesh.vertexCount();
  DisjointSets sets(n);
  for (const Triangle& f : mesh.faces)
    for (int k = 1; k < 3; ++k) sets.unite(static_cast<std::uint32_t>(f[0]), static_cast<std::uint32_t>(f[k]));
  MeshComponents result;
  std::vector<int> label(n, -1);
  result.face_component.resize(mesh.faces.size());
  // Labels follow the order in which faces first reach a component, which
  // keeps them stable for a given file.
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const std::uint32_t root = sets.find(static_cast<std::uint32_t>(mesh.faces[i][0]));
    if (label[root] < 0) label[root] = static_cast<int>(result.count++);
    result.face_component[i] = label[root];
  }
  const std::vector<std::uint8_t> used = referencedVertices(mesh);
  result.unreferenced_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), std::uint8_t{0}));
  return result;
}

}  // namespace icrkit
