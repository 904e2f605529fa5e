#include <icrkit/eval/geodesic_distances.hpp>

#include <icrkit/core/error.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>

namespace icrkit::eval {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Faces around each undirected edge, gathered by sorting (a < b, face, apex)
// records so that the faces of one edge are adjacent.
struct EdgeUse {
  int a, b;
  int apex;  // the face's third vertex
  bool operator<(const EdgeUse& o) const { return std::tie(a, b, apex) < std::tie(o.a, o.b, o.apex); }
};

std::vector<EdgeUse> sortedEdgeUses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> uses;
  uses.reserve(mesh.faces.size() * 3);
  for (const Triangle& f : mesh.faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) continue;  // degenerate: no surface to walk on
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), f[(k + 2) % 3]});
    }
  }
  std::sort(uses.begin(), uses.end());
  return uses;
}

// Length of the straight surface line from `p` to `q` across the two
// triangles (u, v, p) and (u, v, q) unfolded into one plane, or +infinity
// when that line would leave them (the unfolded quadrilateral is not convex
// at u or v), i.e. when it does not cross the open segment u-v.
double unfoldedDiagonal(const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& p,
                        const Eigen::Vector3d& q) {
  const Eigen::Vector3d axis = v - u;
  const double length = axis.norm();
  if (!(length > 0.0)) return kInfinity;
  const Eigen::Vector3d e = axis / length;
  const double px = (p - u).dot(e), qx = (q - u).dot(e);
  const double py = ((p - u) - px * e).norm(), qy = ((q - u) - qx * e).norm();
  if (!(py > 0.0) || !(qy > 0.0)) return kInfinity;
  // p at (px, py), q at (qx, -qy): where the segment crosses the u-v line.
  const double cross = px + (qx - px) * (py / (py + qy));
  if (!(cross > 0.0 && cross < length)) return kInfinity;
  return std::hypot(px - qx, py + qy);
}

}  // namespace

void DistanceWorkspace::prepare(std::size_t vertex_count) {
  if (distance_.size() == vertex_count) return;
  distance_.assign(vertex_count, kInfinity);
  visited_.assign(vertex_count, 0);
  target_.assign(vertex_count, 0);
  visit_epoch_ = 0;
  target_epoch_ = 0;
}

std::uint32_t DistanceWorkspace::nextVisitEpoch() {
  if (++visit_epoch_ == 0) {  // wrapped after 2^32 queries: old marks could alias
    std::fill(visited_.begin(), visited_.end(), 0u);
    visit_epoch_ = 1;
  }
  return visit_epoch_;
}

std::uint32_t DistanceWorkspace::nextTargetEpoch() {
  if (++target_epoch_ == 0) {
    std::fill(target_.begin(), target_.end(), 0u);
    target_epoch_ = 1;
  }
  return target_epoch_;
}

MeshDistanceGraph::MeshDistanceGraph(const TriangleMesh& mesh, const MeshDistanceGraphParameters& params)
    : mesh_(&mesh), params_(params) {
  try {
    mesh.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError("mesh", "", e.what());
  }
  adjacency_ = vertexAdjacency(mesh);
  const std::size_t n = mesh.vertexCount();
  const auto& pos = mesh.vertices.positions;

  // Boundary: an edge with one face; a vertex of no face has no surface
  // around it at all, so it counts too.
  boundary_.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (adjacency_.degree(v) == 0) boundary_[v] = 1;
  const std::vector<EdgeUse> uses = sortedEdgeUses(mesh);
  std::vector<std::vector<std::pair<int, double>>> diagonals;
  if (params_.paths == GeodesicPaths::EdgesAndUnfoldedDiagonals) diagonals.resize(n);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    const int a = uses[i].a, b = uses[i].b;
    if (j - i == 1) {
      boundary_[a] = boundary_[b] = 1;
    } else if (j - i == 2 && !diagonals.empty()) {
      // Only a manifold edge has a well-defined pair of triangles to unfold.
      const int p = uses[i].apex, q = uses[i + 1].apex;
      if (p != q) {
        const double length = unfoldedDiagonal(pos[a], pos[b], pos[p], pos[q]);
        if (std::isfinite(length)) {
          diagonals[p].emplace_back(q, length);
          diagonals[q].emplace_back(p, length);
        }
      }
    }
    i = j;
  }

  link_offsets_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    link_offsets_[v + 1] = link_offsets_[v] + adjacency_.degree(v) + (diagonals.empty() ? 0 : diagonals[v].size());
  link_target_.resize(link_offsets_[n]);
  link_length_.resize(link_offsets_[n]);
  for (std::size_t v = 0; v < n; ++v) {
    std::size_t slot = link_offsets_[v];
    for (const int* w = adjacency_.begin(v); w != adjacency_.end(v); ++w, ++slot) {
      link_target_[slot] = *w;
      link_length_[slot] = (pos[v] - pos[static_cast<std::size_t>(*w)]).norm();
    }
    if (!diagonals.empty()) {
      // Sorted so that the search order, hence tie-breaking, depends on the
      // mesh alone.
      std::sort(diagonals[v].begin(), diagonals[v].end());
      for (const auto& [w, length] : diagonals[v]) {
        link_target_[slot] = w;
        link_length_[slot] = length;
        ++slot;
      }
    }
  }

  // Components by breadth-first search from the lowest unlabelled vertex.
  component_.assign(n, -1);
  std::vector<int> queue;
  for (std::size_t start = 0; start < n; ++start) {
    if (component_[start] >= 0) continue;
    const int label = static_cast<int>(component_count_++);
    component_[start] = label;
    queue.assign(1, static_cast<int>(start));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::size_t v = static_cast<std::size_t>(queue[head]);
      for (const int* w = adjacency_.begin(v); w != adjacency_.end(v); ++w)
        if (component_[static_cast<std::size_t>(*w)] < 0) {
          component_[static_cast<std::size_t>(*w)] = label;
          queue.push_back(*w);
        }
    }
  }
}

void MeshDistanceGraph::checkIndex(int v) const {
  if (v < 0 || static_cast<std::size_t>(v) >= vertexCount())
    throw InputError("vertex index", "", std::to_string(v) + " is out of range, expected 0.." +
                                             std::to_string(static_cast<long long>(vertexCount()) - 1));
}

void MeshDistanceGraph::markTargets(const std::vector<int>& targets, DistanceWorkspace& ws,
                                    std::size_t& distinct) const {
  const std::uint32_t epoch = ws.nextTargetEpoch();
  distinct = 0;
  for (int t : targets) {
    checkIndex(t);
    std::uint32_t& mark = ws.target_[static_cast<std::size_t>(t)];
    if (mark != epoch) {
      mark = epoch;
      ++distinct;
    }
  }
}

template <typename OnSettle>
void MeshDistanceGraph::dijkstra(int source, DistanceWorkspace& ws, double radius, OnSettle&& on_settle) const {
  dijkstra(source, ws, radius, std::forward<OnSettle>(on_settle), [](std::size_t, double) { return false; });
}

template <typename OnSettle, typename Prune>
void MeshDistanceGraph::dijkstra(int source, DistanceWorkspace& ws, double radius, OnSettle&& on_settle,
                                 Prune&& prune) const {
  const std::uint32_t epoch = ws.nextVisitEpoch();
  auto& heap = ws.heap_;
  heap.clear();
  // Pairs compare by distance, then vertex, so equal distances settle the
  // lower index first: this is what makes every answer deterministic.
  const auto later = std::greater<std::pair<double, int>>();
  ws.visited_[static_cast<std::size_t>(source)] = epoch;
  ws.distance_[static_cast<std::size_t>(source)] = 0.0;
  heap.emplace_back(0.0, source);
  std::uint64_t settled = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const auto [d, u] = heap.back();
    heap.pop_back();
    const std::size_t us = static_cast<std::size_t>(u);
    if (d > ws.distance_[us]) continue;  // stale entry of an improved vertex
    if (d > radius) break;
    ++settled;
    if (!on_settle(u, d)) break;
    for (std::size_t slot = link_offsets_[us]; slot < link_offsets_[us + 1]; ++slot) {
      const std::size_t w = static_cast<std::size_t>(link_target_[slot]);
      const double dw = d + link_length_[slot];
      if (dw > radius || prune(w, dw)) continue;
      if (ws.visited_[w] != epoch) {
        ws.visited_[w] = epoch;
      } else if (dw >= ws.distance_[w]) {
        continue;
      }
      ws.distance_[w] = dw;
      heap.emplace_back(dw, static_cast<int>(w));
      std::push_heap(heap.begin(), heap.end(), later);
    }
  }
  ws.settled_total_ += settled;
}

std::vector<double> MeshDistanceGraph::distances(int source, const std::vector<int>& targets, DistanceMetric metric,
                                                 DistanceWorkspace& ws) const {
  checkIndex(source);
  std::vector<double> result(targets.size(), kInfinity);
  if (metric == DistanceMetric::Euclidean) {
    for (std::size_t i = 0; i < targets.size(); ++i) {
      checkIndex(targets[i]);
      result[i] = (position(source) - position(targets[i])).norm();
    }
    return result;
  }
  ws.prepare(vertexCount());
  std::size_t remaining = 0;
  markTargets(targets, ws, remaining);
  const std::uint32_t target_epoch = ws.target_epoch_;
  if (remaining > 0)
    dijkstra(source, ws, kInfinity, [&](int v, double) {
      if (ws.target_[static_cast<std::size_t>(v)] == target_epoch) --remaining;
      return remaining > 0;
    });
  // Targets never reached keep an old distance_ but not this query's epoch.
  const std::uint32_t epoch = ws.visit_epoch_;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const std::size_t t = static_cast<std::size_t>(targets[i]);
    if (ws.visited_[t] == epoch) result[i] = ws.distance_[t];
  }
  return result;
}

NearestVertex MeshDistanceGraph::nearest(int source, const std::vector<int>& targets, DistanceMetric metric,
                                         DistanceWorkspace& ws) const {
  checkIndex(source);
  NearestVertex best;
  if (metric == DistanceMetric::Euclidean) {
    for (int t : targets) {
      checkIndex(t);
      const double d = (position(source) - position(t)).norm();
      if (d < best.distance || (d == best.distance && t < best.vertex)) best = {t, d};
    }
    return best;
  }
  ws.prepare(vertexCount());
  std::size_t distinct = 0;
  markTargets(targets, ws, distinct);
  if (distinct == 0) return best;
  const std::uint32_t target_epoch = ws.target_epoch_;
  dijkstra(source, ws, kInfinity, [&](int v, double d) {
    if (ws.target_[static_cast<std::size_t>(v)] != target_epoch) return true;
    best = {v, d};
    return false;
  });
  return best;
}

double MeshDistanceGraph::eccentricity(int source, const std::vector<int>& targets, DistanceMetric metric,
                                       DistanceWorkspace& ws, double give_up_above) const {
  checkIndex(source);
  if (metric == DistanceMetric::Euclidean) {
    double worst = 0.0;
    for (int t : targets) {
      checkIndex(t);
      worst = std::max(worst, (position(source) - position(t)).norm());
      if (worst > give_up_above) return kInfinity;
    }
    return worst;
  }
  ws.prepare(vertexCount());
  std::size_t remaining = 0;
  markTargets(targets, ws, remaining);
  if (remaining == 0) return 0.0;
  const std::uint32_t target_epoch = ws.target_epoch_;
  double last = 0.0;
  // Settling in distance order, the last target settled is the farthest; a
  // search limited to the radius `give_up_above` that leaves targets
  // unsettled has proven the answer too large.
  auto on_settle = [&](int v, double d) {
    if (ws.target_[static_cast<std::size_t>(v)] == target_epoch) {
      --remaining;
      last = d;
    }
    return remaining > 0;
  };
  if (std::isinf(give_up_above)) {
    dijkstra(source, ws, give_up_above, on_settle);
  } else {
    // A* style pruning: a vertex whose distance plus its straight-line
    // distance to the targets' bounding box exceeds the radius lies on no
    // path to a target within it. Keeps a search around a region from
    // flooding the surface beyond it (e.g. along a handle) at no change to
    // the result.
    Eigen::AlignedBox3d box;
    for (int t : targets) box.extend(position(t));
    dijkstra(source, ws, give_up_above, on_settle, [&](std::size_t w, double dw) {
      // Shrunk a little so that rounding can never prune a path of length
      // exactly give_up_above (a tie must be reported, not given up on).
      return dw + box.exteriorDistance(mesh_->vertices.positions[w]) * (1.0 - 1e-9) > give_up_above;
    });
  }
  return remaining == 0 ? last : kInfinity;
}

std::vector<double> MeshDistanceGraph::geodesicField(int source, DistanceWorkspace& ws, double max_distance) const {
  checkIndex(source);
  ws.prepare(vertexCount());
  std::vector<double> field(vertexCount(), kInfinity);
  dijkstra(source, ws, max_distance, [&](int v, double d) {
    field[static_cast<std::size_t>(v)] = d;
    return true;
  });
  return field;
}

}  // namespace icrkit::eval
