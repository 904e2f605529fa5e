#pragma once
// Z-order (Morton) codes: sorting points or grid cells by them puts what is
// close in space close in memory, which is what the caches reward when an
// algorithm walks over a surface point by point.

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace icrkit {

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
/// order is unique). Parallel; the same order whatever the thread count.
std::vector<std::uint32_t> mortonOrder(const std::vector<Eigen::Vector3d>& points);

}  // namespace icrkit
