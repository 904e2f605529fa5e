#include <icrkit/core/disjoint_sets.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/ndt/normal_orientation.hpp>

#include "nearest_neighbour_row.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace icrkit::ndt {
namespace {

struct Edge {
  std::uint32_t key;  // bits of the float 1 - |n_a . n_b|: ascending = most confident first
  std::uint32_t a;
  std::uint32_t b;
};

std::uint32_t weightKey(const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  const float weight = static_cast<float>(std::clamp(1.0 - std::abs(x.dot(y)), 0.0, 1.0));
  std::uint32_t key;
  std::memcpy(&key, &weight, sizeof key);  // non-negative floats order like their bits
  return key;
}

// Each undirected edge of the graph once: from its smaller end, or from the
// larger one when the smaller does not list it. Ordered by point, then slot.
std::vector<Edge> undirectedEdges(const NeighbourGraph& graph, const std::vector<Eigen::Vector3d>& normals) {
  const std::size_t n = normals.size();
  const std::size_t k = graph.slots;
  auto lists = [&](std::size_t i, std::size_t j) {
    for (std::size_t s = 0; s < k; ++s)
      if (graph.neighbours[i * k + s] == j) return true;
    return false;
  };
  auto keep = [&](std::size_t i, std::size_t s) {
    const std::size_t j = graph.neighbours[i * k + s];
    if (j >= n || j == i) return false;
    for (std::size_t t = 0; t < s; ++t)
      if (graph.neighbours[i * k + t] == j) return false;  // listed twice
    return i < j || !lists(j, i);
  };
  std::vector<std::size_t> first(n + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      for (std::size_t s = 0; s < k; ++s) first[i + 1] += keep(i, s) ? 1 : 0;
  });
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<Edge> edges(first[n]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      std::size_t slot = first[i];
      for (std::size_t s = 0; s < k; ++s)
        if (keep(i, s)) {
          const std::size_t j = graph.neighbours[i * k + s];
          edges[slot++] = {weightKey(normals[i], normals[j]), static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)};
        }
    }
  });
  return edges;
}

// Stable least-significant-digit radix sort on the 32-bit key: edges of equal
// weight keep their point order, so the forest is the same on every run.
void sortByKey(std::vector<Edge>& edges) {
  std::vector<Edge> buffer(edges.size());
  for (int shift = 0; shift < 32; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (const Edge& e : edges) ++start[((e.key >> shift) & 0xFF) + 1];
    if (start[1] == edges.size() && shift > 0) continue;  // every key has digit 0 here
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (const Edge& e : edges) buffer[start[(e.key >> shift) & 0xFF]++] = e;
    edges.swap(buffer);
  }
}

}  // namespace

NeighbourGraph nearestNeighbourGraph(const std::vector<Eigen::Vector3d>& points, std::size_t k) {
  const std::size_t n = points.size();
  NeighbourGraph graph;
  graph.slots = n > 1 ? std::min(k, n - 1) : 0;
  graph.neighbours.assign(n * graph.slots, n);
  if (graph.slots == 0) return graph;
  const KdTree tree(points);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) fillNearestNeighbourRow(tree, points, i, graph);
  });
  return graph;
}

std::size_t orientNormalsOverGraph(PointCloud& cloud, const NeighbourGraph& graph) {
  const std::size_t n = cloud.size();
  if (!cloud.hasNormals() || n == 0) return 0;
  // Tree adjacency counts reach twice the point count in 32 bits.
  if (n > std::numeric_limits<std::uint32_t>::max() / 2)
    throw InputError("point cloud", "", "normal orientation handles at most 2^31 - 1 points, got " + std::to_string(n));
  if (graph.neighbours.size() != n * graph.slots)
    throw InputError("neighbour graph", "", "expected " + std::to_string(n * graph.slots) + " slots, got " +
                                                std::to_string(graph.neighbours.size()));
  auto& normals = cloud.normals;
  const auto& p = cloud.positions;

  // Kruskal's algorithm on the most confident edges first: a maximum
  // spanning forest, the tree Prim's algorithm grows from any seed.
  std::vector<Edge> edges = undirectedEdges(graph, normals);
  sortByKey(edges);
  DisjointSets sets(n);
  std::vector<std::uint32_t> degree(n + 1, 0);
  std::vector<Edge> tree_edges;
  tree_edges.reserve(n);
  for (const Edge& e : edges)
    if (sets.unite(e.a, e.b)) {
      tree_edges.push_back(e);
      ++degree[e.a + 1];
      ++degree[e.b + 1];
    }
  edges = {};
  std::partial_sum(degree.begin(), degree.end(), degree.begin());
  std::vector<std::uint32_t> adjacent(2 * tree_edges.size());
  {
    std::vector<std::uint32_t> fill(degree.begin(), degree.end() - 1);
    for (const Edge& e : tree_edges) {
      adjacent[fill[e.a]++] = e.b;
      adjacent[fill[e.b]++] = e.a;
    }
  }

  // Each tree's root: its point whose normal is most nearly along the
  // direction from the centroid (ties: the smaller index).
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& q : p) centroid += q;
  centroid /= static_cast<double>(n);
  std::vector<double> outwardness(n, -1.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3d r = p[i] - centroid;
      const double length = r.norm();
      if (length > 0 && normals[i].squaredNorm() > 0) outwardness[i] = std::abs(normals[i].dot(r)) / length;
    }
  });
  std::vector<std::uint32_t> root_of_set(n, std::numeric_limits<std::uint32_t>::max());
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t& root = root_of_set[sets.find(i)];
    if (root == std::numeric_limits<std::uint32_t>::max() || outwardness[i] > outwardness[root]) root = i;
  }

  // Walk each tree from its root; a normal that disagrees with the nearest
  // non-zero normal above it turns (a zero normal passes its parent's on).
  // The result depends only on the tree, not on the walk order.
  std::size_t flipped = 0;
  std::vector<std::uint8_t> done(n, 0);
  std::vector<std::uint32_t> reference(n);  // the non-zero normal a node's children compare with
  std::vector<std::uint32_t> stack;
  for (std::uint32_t set = 0; set < n; ++set) {
    const std::uint32_t root = root_of_set[set];
    if (root == std::numeric_limits<std::uint32_t>::max()) continue;
    if (normals[root].dot(p[root] - centroid) < 0) {
      normals[root] = -normals[root];
      ++flipped;
    }
    done[root] = 1;
    reference[root] = root;
    stack.push_back(root);
    while (!stack.empty()) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      for (std::uint32_t s = degree[v]; s < degree[v + 1]; ++s) {
        const std::uint32_t u = adjacent[s];
        if (done[u]) continue;
        done[u] = 1;
        if (normals[u].dot(normals[reference[v]]) < 0) {
          normals[u] = -normals[u];
          ++flipped;
        }
        reference[u] = normals[u].squaredNorm() > 0 ? u : reference[v];
        stack.push_back(u);
      }
    }
  }
  return flipped;
}

std::size_t orientNormals(PointCloud& cloud, const std::optional<Eigen::Vector3d>& viewpoint,
                          const NormalOrientationParameters& params) {
  const std::size_t n = cloud.size();
  if (!cloud.hasNormals() || n == 0) return 0;
  if (viewpoint) {
    std::size_t flipped = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (cloud.normals[i].dot(*viewpoint - cloud.positions[i]) < 0) {
        cloud.normals[i] = -cloud.normals[i];
        ++flipped;
      }
    return flipped;
  }
  return orientNormalsOverGraph(cloud, nearestNeighbourGraph(cloud.positions, params.neighbours));
}

}  // namespace icrkit::ndt
