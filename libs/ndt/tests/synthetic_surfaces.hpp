#pragma once
// Synthetic point clouds sampled from surfaces whose geometry is known
// exactly, so that a test can measure how far a smoothed point is from the
// truth instead of comparing against another implementation.
//
// Units are metres, like everywhere in icrkit. Noise is Gaussian along the
// true surface normal (the error model of a range sensor looking straight at
// the surface), drawn from a seeded std::mt19937_64 so that each test sees the
// same cloud on every run.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace icrkit::test {

struct SyntheticCloud {
  PointCloud cloud;                      ///< the noisy samples, what the smoother sees
  std::vector<Eigen::Vector3d> clean;    ///< the same samples before noise, on the surface
  std::vector<double> edge_distance;     ///< of each clean sample to the nearest edge or border (inf: none)
  std::function<double(const Eigen::Vector3d&)> distance;  ///< unsigned distance to the true surface
};

/// Root mean square distance to the true surface over the points whose clean
/// sample lies farther than `margin` from every edge or border; the window of
/// such a point sees one smooth piece of the surface only.
inline double rmsAwayFromEdges(const SyntheticCloud& s, const std::vector<Eigen::Vector3d>& positions,
                               double margin, std::size_t* counted = nullptr) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (s.edge_distance[i] <= margin) continue;
    const double d = s.distance(positions[i]);
    sum += d * d;
    ++n;
  }
  if (counted) *counted = n;
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

namespace detail {

// Adds `sigma` * N(0, 1) along each normal and fills the cloud.
inline void addNormalNoise(SyntheticCloud& s, const std::vector<Eigen::Vector3d>& normals, double sigma,
                           std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  s.cloud.positions.resize(s.clean.size());
  for (std::size_t i = 0; i < s.clean.size(); ++i) s.cloud.positions[i] = s.clean[i] + sigma * gauss(rng) * normals[i];
}

}  // namespace detail

/// The square [0, n*spacing)^2 in the plane z = 0, a regular grid of n x n
/// points. The border counts as an edge (windows there are one-sided).
inline SyntheticCloud makePlane(std::size_t n, double spacing, double sigma, std::uint64_t seed) {
  SyntheticCloud s;
  const double side = static_cast<double>(n - 1) * spacing;
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const double x = static_cast<double>(i) * spacing, y = static_cast<double>(j) * spacing;
      s.clean.emplace_back(x, y, 0.0);
      normals.emplace_back(Eigen::Vector3d::UnitZ());
      s.edge_distance.push_back(std::min({x, y, side - x, side - y}));
    }
  s.distance = [](const Eigen::Vector3d& p) { return std::abs(p.z()); };
  detail::addNormalNoise(s, normals, sigma, seed);
  return s;
}

/// A sphere of radius `radius` about `centre`, sampled on a Fibonacci
/// lattice with one point per spacing^2 of area (a near-uniform spacing with
/// no poles or seams). It has no edges.
inline SyntheticCloud makeSphere(const Eigen::Vector3d& centre, double radius, double spacing, double sigma,
                                 std::uint64_t seed) {
  SyntheticCloud s;
  const double pi = std::acos(-1.0);
  const auto count = static_cast<std::size_t>(std::lround(4.0 * pi * radius * radius / (spacing * spacing)));
  const double golden_angle = pi * (3.0 - std::sqrt(5.0));
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(count);
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden_angle * static_cast<double>(i);
    const Eigen::Vector3d n(rho * std::cos(phi), rho * std::sin(phi), z);
    normals.push_back(n);
    s.clean.push_back(centre + radius * n);
    s.edge_distance.push_back(std::numeric_limits<double>::infinity());
  }
  s.distance = [centre, radius](const Eigen::Vector3d& p) { return std::abs((p - centre).norm() - radius); };
  detail::addNormalNoise(s, normals, sigma, seed);
  return s;
}

/// The lateral surface of a cylinder about the z axis, z in [0, height]; the
/// two rims count as edges.
inline SyntheticCloud makeCylinder(double radius, double height, double spacing, double sigma, std::uint64_t seed) {
  SyntheticCloud s;
  const double pi = std::acos(-1.0);
  const auto around = static_cast<std::size_t>(std::lround(2.0 * pi * radius / spacing));
  const auto rows = static_cast<std::size_t>(std::lround(height / spacing)) + 1;
  std::vector<Eigen::Vector3d> normals;
  for (std::size_t k = 0; k < rows; ++k)
    for (std::size_t a = 0; a < around; ++a) {
      const double t = 2.0 * pi * static_cast<double>(a) / static_cast<double>(around);
      const double z = static_cast<double>(k) * spacing;
      const Eigen::Vector3d n(std::cos(t), std::sin(t), 0.0);
      normals.push_back(n);
      s.clean.push_back(radius * n + Eigen::Vector3d(0, 0, z));
      s.edge_distance.push_back(std::min(z, height - z));
    }
  s.distance = [radius](const Eigen::Vector3d& p) { return std::abs(p.head<2>().norm() - radius); };
  detail::addNormalNoise(s, normals, sigma, seed);
  return s;
}

/// The six faces of the axis-aligned cube [0, side]^3, each a grid of cells
/// of size `spacing` sampled at the cell centres (so no point lies on an
/// edge and none is shared by two faces). The twelve edges are sharp.
inline SyntheticCloud makeBox(double side, double spacing, double sigma, std::uint64_t seed) {
  SyntheticCloud s;
  const auto cells = static_cast<std::size_t>(std::lround(side / spacing));
  std::vector<Eigen::Vector3d> normals;
  for (int axis = 0; axis < 3; ++axis)
    for (int high = 0; high < 2; ++high) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n(axis) = high ? 1.0 : -1.0;
      for (std::size_t i = 0; i < cells; ++i)
        for (std::size_t j = 0; j < cells; ++j) {
          Eigen::Vector3d p;
          p(axis) = high ? side : 0.0;
          p(u) = (static_cast<double>(i) + 0.5) * spacing;
          p(v) = (static_cast<double>(j) + 0.5) * spacing;
          s.clean.push_back(p);
          normals.push_back(n);
          // On a face, the nearest cube edge is on that face's border.
          s.edge_distance.push_back(std::min({p(u), p(v), side - p(u), side - p(v)}));
        }
    }
  const double h = side / 2.0;
  s.distance = [h](const Eigen::Vector3d& p) {
    // Unsigned distance to the surface of the box centred at (h, h, h).
    const Eigen::Vector3d q = (p - Eigen::Vector3d::Constant(h)).cwiseAbs() - Eigen::Vector3d::Constant(h);
    const double outside = q.cwiseMax(0.0).norm();
    const double inside = std::min(q.maxCoeff(), 0.0);
    return std::abs(outside + inside);
  };
  detail::addNormalNoise(s, normals, sigma, seed);
  return s;
}

}  // namespace icrkit::test
