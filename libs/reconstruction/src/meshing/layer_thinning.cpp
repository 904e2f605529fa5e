#include "layer_thinning.hpp"

#include "cube_key.hpp"

#include <icrkit/core/kd_tree.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace icrkit::reconstruction {

namespace {

// RMS distance of the points `near` indexes from the quadric height field
// z = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 fitted to them in the
// frame of their best-fit plane: the noise, with the surface's curvature
// taken out. -1 when the fit is degenerate.
double quadricResidual(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& near,
                       const Eigen::Vector3d& centre, double window) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t k : near) mean += points[k];
  mean /= double(near.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t k : near) covariance += (points[k] - mean) * (points[k] - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Matrix3d axes = eigen.eigenvectors();  // columns: normal first
  Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Vector3d> local;
  local.reserve(near.size());
  for (std::size_t k : near) {
    // In units of the window: the normal equations stay well scaled.
    const Eigen::Vector3d d = (points[k] - centre) / window;
    const Eigen::Vector3d l(d.dot(axes.col(1)), d.dot(axes.col(2)), d.dot(axes.col(0)));
    local.push_back(l);
    Eigen::Matrix<double, 6, 1> row;
    row << 1.0, l.x(), l.y(), l.x() * l.x(), l.x() * l.y(), l.y() * l.y();
    normal_matrix += row * row.transpose();
    rhs += row * l.z();
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(normal_matrix);
  if (solver.info() != Eigen::Success || !(solver.rcond() > 1e-12)) return -1.0;
  const Eigen::Matrix<double, 6, 1> c = solver.solve(rhs);
  double sum = 0.0;
  for (const Eigen::Vector3d& l : local) {
    const double z = c(0) + c(1) * l.x() + c(2) * l.y() + c(3) * l.x() * l.x() + c(4) * l.x() * l.y() +
                     c(5) * l.y() * l.y();
    sum += (l.z() - z) * (l.z() - z);
  }
  return window * std::sqrt(sum / double(near.size()));
}

}  // namespace

double layerThickness(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint8_t>& skip,
                      double window, std::size_t samples) {
  std::vector<Eigen::Vector3d> used;
  used.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (skip.empty() || !skip[i]) used.push_back(points[i]);
  if (used.size() < 3 || !(window > 0.0) || samples == 0) return 0.0;
  const KdTree tree(used);
  const std::size_t count = std::min(samples, used.size());
  const double stride = double(used.size()) / double(count);
  std::vector<double> sigma(count, -1.0);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t s) {
    const Eigen::Vector3d& centre = used[static_cast<std::size_t>(s * stride)];
    std::vector<std::size_t> near;
    tree.indicesWithinRadius(centre, window, near);
    if (near.size() < 12) return;
    sigma[s] = quadricResidual(used, near, centre, window);
  });
  sigma.erase(std::remove_if(sigma.begin(), sigma.end(), [](double x) { return x < 0.0; }), sigma.end());
  if (sigma.empty()) return 0.0;
  const auto middle = sigma.begin() + static_cast<std::ptrdiff_t>(sigma.size() / 2);
  std::nth_element(sigma.begin(), middle, sigma.end());
  return *middle;
}

std::vector<std::uint8_t> thinToCells(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<std::uint8_t>& skip, double cell) {
  std::vector<std::uint8_t> keep(points.size(), 0);
  struct Cube {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::size_t count = 0;
    std::size_t best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
  };
  std::vector<std::int64_t> keys(points.size(), 0);
  std::unordered_map<std::int64_t, Cube> cubes;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!skip.empty() && skip[i]) continue;
    keys[i] = cubeKey(points[i], cell);
    Cube& c = cubes[keys[i]];
    c.sum += points[i];
    ++c.count;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!skip.empty() && skip[i]) continue;
    Cube& c = cubes[keys[i]];
    const double d = (points[i] - c.sum / double(c.count)).squaredNorm();
    if (d < c.best_distance) {  // strict: the lower index wins a tie
      c.best_distance = d;
      c.best = i;
    }
  }
  for (const auto& [k, c] : cubes) keep[c.best] = 1;
  return keep;
}

}  // namespace icrkit::reconstruction
