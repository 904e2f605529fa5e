#include <icrkit/core/kd_tree.hpp>
#include <icrkit/ndt/normal_orientation.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <queue>
#include <tuple>
#include <vector>

namespace icrkit::ndt {

std::size_t orientNormals(PointCloud& cloud, const std::optional<Eigen::Vector3d>& viewpoint,
                          const NormalOrientationParameters& params) {
  const std::size_t n = cloud.size();
  if (!cloud.hasNormals() || n == 0) return 0;
  auto& normals = cloud.normals;
  const auto& p = cloud.positions;
  std::size_t flipped = 0;
  if (viewpoint) {
    for (std::size_t i = 0; i < n; ++i)
      if (normals[i].dot(*viewpoint - p[i]) < 0) {
        normals[i] = -normals[i];
        ++flipped;
      }
    return flipped;
  }

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& q : p) centroid += q;
  centroid /= static_cast<double>(n);

  // k-NN graph (without the point itself).
  const std::size_t k = std::min(params.neighbours, n - 1);
  std::vector<std::size_t> graph(n * k, n);
  const KdTree tree(p);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      std::size_t slot = 0;
      for (const Neighbour& nb : tree.nearest(p[i], k + 1))
        if (nb.index != i && slot < k) graph[i * k + slot++] = nb.index;
    }
  });

  // Prim's algorithm from seeds; a max-heap on confidence |n_i . n_j| with
  // the index as tie-breaker keeps the traversal deterministic.
  std::vector<std::uint8_t> done(n, 0);
  struct Candidate {
    double confidence;
    std::size_t node;
    std::size_t parent;
    bool operator<(const Candidate& o) const {
      return confidence < o.confidence || (confidence == o.confidence && node > o.node);
    }
  };
  // best[m]: the highest confidence with which m has been offered; a weaker
  // offer can never win, so it is not pushed (Prim's eager variant: same
  // tree, a much smaller heap).
  std::vector<double> best(n, -1.0);
  auto visit = [&](std::size_t seed) {
    std::priority_queue<Candidate> heap;
    heap.push({2.0, seed, seed});
    while (!heap.empty()) {
      const Candidate c = heap.top();
      heap.pop();
      if (done[c.node]) continue;
      done[c.node] = 1;
      if (c.node != c.parent && normals[c.node].dot(normals[c.parent]) < 0) {
        normals[c.node] = -normals[c.node];
        ++flipped;
      }
      for (std::size_t s = 0; s < k; ++s) {
        const std::size_t m = graph[c.node * k + s];
        if (m >= n || done[m]) continue;
        const double confidence = std::abs(normals[c.node].dot(normals[m]));
        if (confidence > best[m]) {
          best[m] = confidence;
          heap.push({confidence, m, c.node});
        }
      }
    }
  };

  // Seeds in order of how clearly their normal points away from the centroid.
  std::vector<std::size_t> order(n);
  std::vector<double> outwardness(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    order[i] = i;
    const Eigen::Vector3d r = p[i] - centroid;
    const double length = r.norm();
    outwardness[i] = length > 0 && normals[i].squaredNorm() > 0 ? std::abs(normals[i].dot(r)) / length : -1.0;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return outwardness[a] > outwardness[b]; });
  for (std::size_t seed : order) {
    if (done[seed]) continue;
    if (normals[seed].dot(p[seed] - centroid) < 0) {
      normals[seed] = -normals[seed];
      ++flipped;
    }
    visit(seed);
  }
  return flipped;
}

}  // namespace icrkit::ndt
