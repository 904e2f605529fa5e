#include <icrkit/icr/recommended_contact.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>

namespace icrkit::icr {

RecommendedContact recommendedContact(const GraspableObject& object, const std::vector<int>& region) {
  RecommendedContact best;
  if (region.empty()) return best;
  const VertexAdjacency& adjacency = object.adjacency();
  auto inRegion = [&](int v) { return std::binary_search(region.begin(), region.end(), v); };
  // Multi-source Dijkstra from the border, over edges between region vertices.
  std::unordered_map<int, double> depth;
  depth.reserve(region.size() * 2);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : region) {
    const std::size_t vs = static_cast<std::size_t>(v);
    centroid += object.position(vs);
    bool border = object.onMeshBoundary(vs);
    for (const int* it = adjacency.begin(vs); !border && it != adjacency.end(vs); ++it) border = !inRegion(*it);
    depth[v] = border ? 0.0 : std::numeric_limits<double>::infinity();
    if (border) queue.emplace(0.0, v);
  }
  centroid /= static_cast<double>(region.size());
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > depth[v]) continue;
    const std::size_t vs = static_cast<std::size_t>(v);
    for (const int* it = adjacency.begin(vs); it != adjacency.end(vs); ++it) {
      const auto found = depth.find(*it);
      if (found == depth.end()) continue;
      const double through = d + (object.position(static_cast<std::size_t>(*it)) - object.position(vs)).norm();
      if (through < found->second) {
        found->second = through;
        queue.emplace(through, *it);
      }
    }
  }
  // A region with no border (a whole closed component) has infinite depths:
  // every vertex is as deep as any other, and the centroid decides.
  double best_offset = std::numeric_limits<double>::infinity();
  best.depth_m = -1.0;
  for (int v : region) {
    const double d = depth[v];
    const double offset = (object.position(static_cast<std::size_t>(v)) - centroid).norm();
    if (d > best.depth_m || (d == best.depth_m && offset < best_offset)) {
      best.vertex = v;
      best.depth_m = d;
      best_offset = offset;
    }
  }
  if (!std::isfinite(best.depth_m)) best.depth_m = 0.0;  // reported as unknown rather than infinite
  return best;
}

}  // namespace icrkit::icr
