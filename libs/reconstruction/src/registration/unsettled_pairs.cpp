#include "unsettled_pairs.hpp"

#include "view_pairs.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace icrkit::reconstruction {

std::vector<std::size_t> unsettledPairs(const std::vector<PairRegistrationRecord>& pairs,
                                        const std::vector<Eigen::Isometry3d>& before,
                                        const std::vector<Eigen::Isometry3d>& after,
                                        const std::vector<std::optional<Eigen::Vector3d>>& centroids,
                                        double min_inlier_fraction, double move) {
  const std::size_t n = before.size();
  if (after.size() != n || centroids.size() != n)
    throw std::invalid_argument("unsettledPairs: expected as many poses after and centroids as poses before");
  DisjointSets components = linkedViews(pairs, n);
  std::vector<std::size_t> unsettled;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const PairRegistrationRecord& pair = pairs[k];
    if (pair.from >= n || pair.to >= n)
      throw std::invalid_argument("unsettledPairs: pair " + std::to_string(k) + " names a view beyond the poses");
    if (pair.accepted || !(pair.icp_inlier_fraction < min_inlier_fraction) || !centroids[pair.to] ||
        components.find(std::uint32_t(pair.from)) == components.find(std::uint32_t(pair.to)))
      continue;
    const Eigen::Vector3d& c = *centroids[pair.to];
    const Eigen::Vector3d was = (before[pair.from].inverse() * before[pair.to]) * c;
    const Eigen::Vector3d is = (after[pair.from].inverse() * after[pair.to]) * c;
    if ((is - was).norm() > move) unsettled.push_back(k);
  }
  return unsettled;
}

}  // namespace icrkit::reconstruction
