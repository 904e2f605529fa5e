#pragma once
// Blue-noise samples of closed surfaces with exact normals: dart throwing
// with a minimum distance, so that the spacing is as even as a scanner's and
// the expected topology (sphere: Euler characteristic 2, torus: 0) is known.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <unordered_map>
#include <vector>

namespace icrkit::test {

// Accepts candidate points (drawn uniformly by area by `draw`) that keep at
// least `min_distance` from every accepted one, until `attempts` candidates
// in a row were rejected.
inline PointCloud dartThrowing(const std::function<void(std::mt19937_64&, Eigen::Vector3d&, Eigen::Vector3d&)>& draw,
                               double min_distance, std::uint64_t seed, int attempts = 2000) {
  std::mt19937_64 rng(seed);
  PointCloud cloud;
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  auto key = [&](long x, long y, long z) { return (x * 73856093LL) ^ (y * 19349663LL) ^ (z * 83492791LL); };
  auto cell = [&](double c) { return static_cast<long>(std::floor(c / min_distance)); };
  int misses = 0;
  while (misses < attempts) {
    Eigen::Vector3d p, n;
    draw(rng, p, n);
    const long cx = cell(p.x()), cy = cell(p.y()), cz = cell(p.z());
    bool free = true;
    for (long dx = -1; dx <= 1 && free; ++dx)
      for (long dy = -1; dy <= 1 && free; ++dy)
        for (long dz = -1; dz <= 1 && free; ++dz) {
          auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (int q : it->second)
            if ((cloud.positions[q] - p).squaredNorm() < min_distance * min_distance) {
              free = false;
              break;
            }
        }
    if (!free) {
      ++misses;
      continue;
    }
    misses = 0;
    grid[key(cx, cy, cz)].push_back(static_cast<int>(cloud.positions.size()));
    cloud.positions.push_back(p);
    cloud.normals.push_back(n);
  }
  return cloud;
}

inline PointCloud sampleSphere(double radius, double min_distance, std::uint64_t seed) {
  return dartThrowing(
      [radius](std::mt19937_64& rng, Eigen::Vector3d& p, Eigen::Vector3d& n) {
        std::normal_distribution<double> g(0.0, 1.0);
        do n = Eigen::Vector3d(g(rng), g(rng), g(rng));
        while (n.squaredNorm() < 1e-12);
        n.normalize();
        p = radius * n;
      },
      min_distance, seed);
}

// Torus around the z axis: tube radius r at distance R from the axis.
inline PointCloud sampleTorus(double R, double r, double min_distance, std::uint64_t seed) {
  return dartThrowing(
      [R, r](std::mt19937_64& rng, Eigen::Vector3d& p, Eigen::Vector3d& n) {
        std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), unit(0.0, 1.0);
        double u, v;
        // The area element is proportional to R + r cos v.
        do {
          u = angle(rng);
          v = angle(rng);
        } while (unit(rng) * (R + r) > R + r * std::cos(v));
        n = Eigen::Vector3d(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
        p = Eigen::Vector3d(R * std::cos(u), R * std::sin(u), 0.0) + r * n;
      },
      min_distance, seed);
}

}  // namespace icrkit::test
