#include <icrkit/eval/region_quality.hpp>

#include <icrkit/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace icrkit::eval {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Straight-line lengths and summed edge lengths are rounded differently; a
// Euclidean bound is shrunk by this much before it may prune a geodesic
// candidate, so that rounding never discards the true optimum (path sums
// of thousands of edges carry relative errors ~1e-13).
constexpr double kBoundSlack = 1e-9;
// Extreme vertices (farthest-point sampling) whose distances give every
// candidate its first, cheap eccentricity bound.
constexpr std::size_t kExtremes = 16;
// Geodesic evaluations tolerated before geodesic anchors are added (and the
// first batch's size; later batches double).
constexpr std::size_t kAnchorPatience = 8;

std::vector<int> sortedDistinct(const MeshDistanceGraph& graph, const std::vector<int>& vertices,
                                const char* source) {
  const std::size_t n = graph.vertexCount();
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (vertices[i] < 0 || static_cast<std::size_t>(vertices[i]) >= n)
      throw InputError(source, "entry " + std::to_string(i),
                       "vertex " + std::to_string(vertices[i]) + " is out of range, expected 0.." +
                           std::to_string(static_cast<long long>(n) - 1));
  std::vector<int> set = vertices;
  std::sort(set.begin(), set.end());
  set.erase(std::unique(set.begin(), set.end()), set.end());
  return set;
}

// The component holding most of `set` (ties: the one holding the lowest
// index, `set` being sorted); the vertices elsewhere are removed.
std::size_t keepLargestComponent(const MeshDistanceGraph& graph, std::vector<int>& set) {
  if (graph.componentCount() <= 1 || set.size() <= 1) return 0;
  std::vector<std::pair<int, int>> by_component;  // (component, first position in set)
  by_component.reserve(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) by_component.emplace_back(graph.component(set[i]), static_cast<int>(i));
  std::sort(by_component.begin(), by_component.end());
  int best_component = -1, best_first = 0;
  std::size_t best_count = 0;
  for (std::size_t i = 0; i < by_component.size();) {
    std::size_t j = i;
    while (j < by_component.size() && by_component[j].first == by_component[i].first) ++j;
    const std::size_t count = j - i;
    const int first = by_component[i].second;
    if (count > best_count || (count == best_count && first < best_first)) {
      best_component = by_component[i].first;
      best_first = first;
      best_count = count;
    }
    i = j;
  }
  const std::size_t before = set.size();
  set.erase(std::remove_if(set.begin(), set.end(), [&](int v) { return graph.component(v) != best_component; }),
            set.end());
  return before - set.size();
}

}  // namespace

CentralPoint centralPoint(const MeshDistanceGraph& graph, const std::vector<int>& vertices, DistanceMetric metric,
                          DistanceWorkspace& workspace) {
  std::vector<int> set = sortedDistinct(graph, vertices, "vertex index");
  CentralPoint result;
  if (metric == DistanceMetric::Geodesic) result.ignored = keepLargestComponent(graph, set);
  result.vertices = set.size();
  const std::size_t k = set.size();
  if (k == 0) return result;
  if (k == 1) {
    result.vertex = set[0];
    return result;
  }

  std::vector<Eigen::Vector3d> p(k);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < k; ++i) {
    p[i] = graph.position(set[i]);
    centroid += p[i];
  }
  centroid /= static_cast<double>(k);

  // Cheap lower bounds: the largest distance to a few well-spread extreme
  // vertices, which for a compact region is already close to the full
  // Euclidean eccentricity.
  std::vector<double> bound(k, 0.0), spread(k, kInfinity);
  std::size_t extreme = 0;
  double far = -1.0;
  for (std::size_t i = 0; i < k; ++i) {
    const double d = (p[i] - centroid).norm();
    if (d > far) far = d, extreme = i;
  }
  for (std::size_t s = 0; s < kExtremes; ++s) {
    std::size_t next = 0;
    double next_spread = -1.0;
    for (std::size_t i = 0; i < k; ++i) {
      const double d = (p[i] - p[extreme]).norm();
      bound[i] = std::max(bound[i], d);
      spread[i] = std::min(spread[i], d);
      if (spread[i] > next_spread) next_spread = spread[i], next = i;
    }
    if (!(next_spread > 0.0)) break;  // every vertex is already an extreme (or coincides with one)
    extreme = next;
  }

  std::vector<std::size_t> order(k);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto by_bound = [&](std::size_t a, std::size_t b) { return bound[a] != bound[b] ? bound[a] < bound[b] : a < b; };
  std::sort(order.begin(), order.end(), by_bound);

  const bool geodesic = metric == DistanceMetric::Geodesic;
  const double slack = geodesic ? 1.0 - kBoundSlack : 1.0;
  double best = kInfinity;
  std::size_t best_i = k;
  std::vector<char> done(k, 0);
  auto consider = [&](std::size_t i, double eccentricity) {
    done[i] = 1;
    ++result.evaluations;
    if (best_i == k || eccentricity < best || (eccentricity == best && set[i] < set[best_i])) {
      best = eccentricity;
      best_i = i;
    }
  };

  // Geodesic anchors, added in batches when the Euclidean bounds prune
  // poorly (regions curved around a handle or an edge, where straight lines
  // cut short): full distance fields from well-spread vertices, chosen by
  // geodesic farthest-point sampling starting at the best candidate. Each
  // field is an anchor's exact eccentricity as well as, by symmetry of
  // distance, a lower bound d(anchor, v) <= ecc(v) for every v.
  std::vector<double> anchor_spread;  // geodesic distance to the nearest anchor
  std::size_t anchors = 0, next_anchor = k;
  auto addAnchors = [&](std::size_t count) {
    if (anchor_spread.empty()) {
      anchor_spread.assign(k, kInfinity);
      next_anchor = best_i;
    }
    for (std::size_t a = 0; a < count && next_anchor < k; ++a, ++anchors) {
      const std::size_t s = next_anchor;
      const std::vector<double> d = graph.distances(set[s], set, DistanceMetric::Geodesic, workspace);
      if (!done[s]) consider(s, *std::max_element(d.begin(), d.end()));
      double farthest = 0.0;
      next_anchor = k;
      for (std::size_t j = 0; j < k; ++j) {
        bound[j] = std::max(bound[j], d[j]);
        anchor_spread[j] = std::min(anchor_spread[j], d[j]);
        if (anchor_spread[j] > farthest) farthest = anchor_spread[j], next_anchor = j;
      }
    }
  };

  std::size_t since_anchors = 0;
  for (std::size_t at = 0; at < k; ++at) {
    const std::size_t i = order[at];
    if (done[i]) continue;
    if (bound[i] * slack > best) break;  // sorted: no later candidate can do better either
    // Full Euclidean eccentricity, abandoned once it rules the candidate out.
    double euclidean = bound[i];
    for (std::size_t j = 0; j < k && euclidean * slack <= best; ++j)
      euclidean = std::max(euclidean, (p[i] - p[j]).norm());
    if (euclidean * slack > best) continue;
    consider(i, geodesic ? graph.eccentricity(set[i], set, DistanceMetric::Geodesic, workspace, best) : euclidean);
    const std::size_t patience = std::max(kAnchorPatience, anchors);
    if (geodesic && ++since_anchors >= patience && next_anchor != k + 1) {
      const std::size_t before = anchors;
      addAnchors(patience);
      if (anchors == before) next_anchor = k + 1;  // every vertex is an anchor already: stop trying
      since_anchors = 0;
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(at) + 1, order.end(), by_bound);
    }
  }
  result.vertex = set[best_i];
  result.eccentricity_m = best;
  return result;
}

std::vector<int> regionBorder(const MeshDistanceGraph& graph, const std::vector<int>& region) {
  const std::vector<int> set = sortedDistinct(graph, region, "vertex index");
  const VertexAdjacency& adjacency = graph.adjacency();
  std::vector<int> border;
  for (int v : set) {
    bool on_border = graph.onMeshBoundary(v);
    const std::size_t vs = static_cast<std::size_t>(v);
    for (const int* w = adjacency.begin(vs); !on_border && w != adjacency.end(vs); ++w)
      on_border = !std::binary_search(set.begin(), set.end(), *w);
    if (on_border) border.push_back(v);
  }
  return border;
}

RegionQualityEvaluator::RegionQualityEvaluator(const TriangleMesh& cad_mesh, const RegionQualityParameters& params)
    : params_(params), graph_(cad_mesh, MeshDistanceGraphParameters{params.paths}) {}

CadRegionSummary RegionQualityEvaluator::summarize(const std::vector<int>& cad_region,
                                                   DistanceWorkspace& workspace) const {
  if (cad_region.empty()) throw InputError("CAD region", "", "the region is empty, expected at least one vertex");
  CadRegionSummary cad;
  cad.vertices = sortedDistinct(graph_, cad_region, "CAD region");
  cad.border = regionBorder(graph_, cad.vertices);
  cad.center = centralPoint(graph_, cad.vertices, params_.metric, workspace);
  if (!std::binary_search(cad.border.begin(), cad.border.end(), cad.center.vertex))
    cad.d1_m = graph_.nearest(cad.center.vertex, cad.border, params_.metric, workspace).distance;
  return cad;
}

RegionQuality RegionQualityEvaluator::evaluate(const CadRegionSummary& cad, const std::vector<int>& mapped_region,
                                               DistanceWorkspace& workspace) const {
  const std::vector<int> mapped = sortedDistinct(graph_, mapped_region, "mapped region");
  RegionQuality q;
  q.cad_center = cad.center.vertex;
  q.d1_m = cad.d1_m;
  q.cad_vertices = cad.vertices.size();
  q.cad_border_vertices = cad.border.size();
  q.mapped_vertices = mapped.size();
  if (mapped.empty()) {
    q.reason = "empty mapped region";
    return q;
  }
  const CentralPoint center = centralPoint(graph_, mapped, params_.metric, workspace);
  q.mapped_center = center.vertex;
  q.mapped_ignored = center.ignored;
  q.mapped_center_inside = std::binary_search(cad.vertices.begin(), cad.vertices.end(), center.vertex);
  const bool on_border = std::binary_search(cad.border.begin(), cad.border.end(), center.vertex);
  const double distance =
      on_border ? 0.0 : graph_.nearest(center.vertex, cad.border, params_.metric, workspace).distance;
  q.d2_m = q.mapped_center_inside ? distance : -distance;
  if (std::isinf(q.d1_m)) {
    q.reason = "the CAD region has no border: it covers a whole closed component";
  } else if (!std::isfinite(distance)) {
    q.reason = "mapped central point cannot reach the CAD region";
  } else if (!(q.d1_m > 0.0)) {
    q.reason = "d1 = 0: the CAD central point is on the border";
  } else {
    q.quality = q.d2_m / q.d1_m;
  }
  return q;
}

RegionQuality RegionQualityEvaluator::evaluate(const std::vector<int>& cad_region,
                                               const std::vector<int>& mapped_region,
                                               DistanceWorkspace& workspace) const {
  return evaluate(summarize(cad_region, workspace), mapped_region, workspace);
}

}  // namespace icrkit::eval
