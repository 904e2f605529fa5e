#pragma once
// The cube of a regular grid that holds a point, as one integer: what the
// registration's voxel models and overlaps and the meshing's layer thinning
// key their cubes by.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace icrkit::reconstruction {

/// The cube of edge `size` (metres) holding p: 21 bits per axis, i.e.
/// +-2^20 cubes (+-10 km at 1 cm), clamped beyond.
inline std::int64_t cubeKey(const Eigen::Vector3d& p, double size) {
  constexpr std::int64_t kHalf = 1 << 20;
  std::int64_t key = 0;
  for (int k = 0; k < 3; ++k) {
    const double c = std::clamp(std::floor(p(k) / size), -double(kHalf), double(kHalf - 1));
    key = (key << 21) | (static_cast<std::int64_t>(c) + kHalf);
  }
  return key;
}

}  // namespace icrkit::reconstruction
