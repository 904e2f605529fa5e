#include <icrkit/core/morton_order.hpp>
#include <icrkit/core/radius_cells.hpp>

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace icrkit {
namespace {

// Cube coordinates are offset to be non-negative below 2^21 per axis (the
// Morton code's range): 2^21 cubes of even 1 mm span 2 km.
constexpr std::int64_t kAxisCubes = std::int64_t{1} << 21;

}  // namespace

RadiusCells::RadiusCells(const std::vector<Eigen::Vector3d>& points, double radius)
    : radius_(radius), edge_(radius) {
  if (!(radius > 0) || !std::isfinite(radius)) throw std::invalid_argument("RadiusCells: radius must be > 0");
  if (points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("RadiusCells: more than 2^32 - 1 points");
  if (points.empty()) return;
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) throw std::invalid_argument("RadiusCells: non-finite point");
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  origin_ = lo;
  // A hair above the radius: two points exactly one radius apart could
  // otherwise round into cubes two apart. Larger cubes (a cloud spanning
  // more than 2^21 radii) still hold every neighbour within 27 of them.
  edge_ = std::max(radius * (1.0 + 1e-8), (hi - lo).maxCoeff() / static_cast<double>(kAxisCubes - 2));
  auto cubeOf = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = (p - lo) / edge_;
    std::array<std::int64_t, 3> cube;
    for (int a = 0; a < 3; ++a) cube[a] = std::min<std::int64_t>(static_cast<std::int64_t>(q[a]), kAxisCubes - 1);
    return cube;
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::array<std::int64_t, 3> cube = cubeOf(points[i]);
    keyed[i] = {mortonCode(cube[0], cube[1], cube[2]), static_cast<std::uint32_t>(i)};
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  order_.resize(points.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    order_[k] = keyed[k].second;
    if (k == 0 || keyed[k].first != keyed[k - 1].first) {
      codes_.push_back(keyed[k].first);
      cell_start_.push_back(k);
      for (std::int64_t coordinate : cubeOf(points[keyed[k].second]))
        coords_.push_back(static_cast<std::int32_t>(coordinate));
    }
  }
  cell_start_.push_back(points.size());
}

void RadiusCells::neighbourCells(std::size_t c, std::vector<std::size_t>& out) const {
  out.clear();
  const std::int64_t x = coords_[3 * c], y = coords_[3 * c + 1], z = coords_[3 * c + 2];
  std::uint64_t around[27];
  int count = 0;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        if (x + dx < 0 || y + dy < 0 || z + dz < 0 || x + dx >= kAxisCubes || y + dy >= kAxisCubes ||
            z + dz >= kAxisCubes)
          continue;
        around[count++] = mortonCode(x + dx, y + dy, z + dz);
      }
  std::sort(around, around + count);
  for (int k = 0; k < count; ++k) {
    const auto it = std::lower_bound(codes_.begin(), codes_.end(), around[k]);
    if (it != codes_.end() && *it == around[k]) out.push_back(static_cast<std::size_t>(it - codes_.begin()));
  }
}

}  // namespace icrkit
