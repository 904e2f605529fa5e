#include "view_overlap.hpp"

#include "cube_key.hpp"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace icrkit::reconstruction {

std::vector<std::int64_t> occupiedCubeKeys(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose,
                                           double cube) {
  std::vector<std::int64_t> keys;
  keys.reserve(points.size());
  for (const Eigen::Vector3d& p : points) keys.push_back(cubeKey(pose * p, cube));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

CubeOverlap cubeOverlap(const std::vector<std::vector<Eigen::Vector3d>>& points,
                        const std::vector<Eigen::Isometry3d>& poses, double cube) {
  const std::size_t n = std::min(points.size(), poses.size());
  // Per cube, the views occupying it, in view order.
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> views_in;
  std::vector<std::size_t> counts(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::vector<std::int64_t> keys = occupiedCubeKeys(points[i], poses[i], cube);
    counts[i] = keys.size();
    for (std::int64_t k : keys) views_in[k].push_back(static_cast<std::uint32_t>(i));
  }
  const Eigen::Index size = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd together = Eigen::MatrixXd::Zero(size, size);
  std::vector<std::size_t> shared(n, 0);
  for (const auto& [key, views] : views_in) {
    if (views.size() < 2) continue;
    for (std::uint32_t a : views) {
      ++shared[a];
      for (std::uint32_t b : views)
        if (a != b) together(a, b) += 1.0;
    }
  }
  CubeOverlap out;
  out.shared.assign(n, 0.0);
  out.pair = Eigen::MatrixXd::Zero(size, size);
  for (std::size_t i = 0; i < n; ++i) {
    if (counts[i] == 0) continue;
    out.shared[i] = double(shared[i]) / double(counts[i]);
    out.pair.row(static_cast<Eigen::Index>(i)) = together.row(static_cast<Eigen::Index>(i)) / double(counts[i]);
  }
  return out;
}

std::vector<std::vector<std::size_t>> linkedGroups(const Eigen::MatrixXd& pair, const std::vector<std::size_t>& views,
                                                   double min_share) {
  auto linked = [&](std::size_t a, std::size_t b) {
    const auto x = static_cast<Eigen::Index>(a), y = static_cast<Eigen::Index>(b);
    return std::max(pair(x, y), pair(y, x)) >= min_share;
  };
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::uint8_t> left(views.size(), 1);
  for (std::size_t a = 0; a < views.size(); ++a) {
    if (!left[a]) continue;
    left[a] = 0;
    std::vector<std::size_t> group{a};
    for (std::size_t k = 0; k < group.size(); ++k)
      for (std::size_t b = 0; b < views.size(); ++b)
        if (left[b] && linked(views[group[k]], views[b])) {
          left[b] = 0;
          group.push_back(b);
        }
    std::sort(group.begin(), group.end());
    for (std::size_t& g : group) g = views[g];
    groups.push_back(std::move(group));
  }
  return groups;
}

std::vector<std::uint8_t> largestLinkedGroup(const Eigen::MatrixXd& pair, double min_share) {
  const std::size_t n = static_cast<std::size_t>(pair.rows());
  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::vector<std::size_t>> groups = linkedGroups(pair, all, min_share);
  std::vector<std::uint8_t> in(n, 0);
  const std::vector<std::size_t>* largest = nullptr;
  for (const std::vector<std::size_t>& g : groups)
    if (!largest || g.size() > largest->size()) largest = &g;  // strictly larger: ties keep the first
  if (largest)
    for (std::size_t v : *largest) in[v] = 1;
  return in;
}

void OccupiedCubes::add(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) {
  for (const Eigen::Vector3d& p : points) keys_.insert(cubeKey(pose * p, cube_));
}

double OccupiedCubes::shareOf(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) const {
  const std::vector<std::int64_t> keys = occupiedCubeKeys(points, pose, cube_);
  if (keys.empty()) return 0.0;
  std::size_t shared = 0;
  for (std::int64_t k : keys) shared += keys_.count(k);
  return double(shared) / double(keys.size());
}

}  // namespace icrkit::reconstruction
