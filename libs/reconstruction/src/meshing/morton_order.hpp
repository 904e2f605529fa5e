#pragma once
// Z-order (Morton) codes: sorting points or grid cells by them puts what is
// close in space close in memory, which is what the caches reward when an
// algorithm walks over a surface point by point.

#include <Eigen/Core>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace icrkit::reconstruction {

/// Interleaved bits of three cell coordinates, each clamped to [0, 2^21).
inline std::uint64_t mortonCode(std::int64_t x, std::int64_t y, std::int64_t z) {
  auto spread = [](std::int64_t v) {
    std::uint64_t b = static_cast<std::uint64_t>(std::clamp<std::int64_t>(v, 0, (1 << 21) - 1));
    b = (b | (b << 32)) & 0x1f00000000ffffULL;
    b = (b | (b << 16)) & 0x1f0000ff0000ffULL;
    b = (b | (b << 8)) & 0x100f00f00f00f00fULL;
    b = (b | (b << 4)) & 0x10c30c30c30c30c3ULL;
    b = (b | (b << 2)) & 0x1249249249249249ULL;
    return b;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

/// The point indices sorted by the Morton code of their position in a
/// 2^21-cell-per-axis grid over the bounding box (ties by index, so the
/// order is unique).
inline std::vector<std::uint32_t> mortonOrder(const std::vector<Eigen::Vector3d>& points) {
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

}  // namespace icrkit::reconstruction
