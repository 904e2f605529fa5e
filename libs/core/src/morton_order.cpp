#include <icrkit/core/morton_order.hpp>

#include <tbb/parallel_sort.h>

#include <limits>
#include <utility>

namespace icrkit {

std::vector<std::uint32_t> mortonOrder(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  const double scale = extent > 0 ? static_cast<double>((1 << 21) - 1) / extent : 0.0;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d c = (points[i] - lo) * scale;
    keyed[i] = {mortonCode(static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()),
                           static_cast<std::int64_t>(c.z())),
                static_cast<std::uint32_t>(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace icrkit
