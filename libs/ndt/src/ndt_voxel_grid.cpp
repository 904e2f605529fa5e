#include "ndt_voxel_grid.hpp"

#include <icrkit/core/error.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>

namespace icrkit::ndt {

namespace {

// 21 bits per axis: +-2^20 cells, i.e. +-10 km at 1 cm, far beyond any scan.
constexpr std::int64_t kHalfRange = 1 << 20;

// A dense cell table up to this many entries (4 MB).
constexpr double kMaxDenseEntries = 1 << 20;

bool inRange(const Eigen::Vector3i& c) {
  for (int k = 0; k < 3; ++k)
    if (c(k) < -kHalfRange || c(k) >= kHalfRange) return false;
  return true;
}

std::int64_t pack(const Eigen::Vector3i& c) {
  return ((c(0) + kHalfRange) << 42) | ((c(1) + kHalfRange) << 21) | (c(2) + kHalfRange);
}

}  // namespace

Eigen::Vector3i NdtVoxelGrid::cellOf(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d scaled = point / resolution_;
  // Clamp before the cast: a point far outside turns into an out-of-range
  // cell, never into undefined behaviour.
  Eigen::Vector3i c;
  for (int k = 0; k < 3; ++k)
    c(k) = static_cast<int>(std::clamp(std::floor(scaled(k)), -2.0 * kHalfRange, 2.0 * kHalfRange));
  return c;
}

std::size_t NdtVoxelGrid::denseSlot(const Eigen::Vector3i& offset) const {
  return (static_cast<std::size_t>(offset(0)) * static_cast<std::size_t>(dense_size_(1)) +
          static_cast<std::size_t>(offset(1))) *
             static_cast<std::size_t>(dense_size_(2)) +
         static_cast<std::size_t>(offset(2));
}

int NdtVoxelGrid::find(const Eigen::Vector3i& cell) const {
  if (!dense_.empty()) {
    const Eigen::Vector3i d = cell - dense_origin_;
    if (d(0) < 0 || d(1) < 0 || d(2) < 0 || d(0) >= dense_size_(0) || d(1) >= dense_size_(1) || d(2) >= dense_size_(2))
      return -1;
    return dense_[denseSlot(d)];
  }
  if (!inRange(cell)) return -1;
  const auto it = index_.find(pack(cell));
  return it == index_.end() ? -1 : it->second;
}

NdtVoxelGrid::NdtVoxelGrid(const std::vector<Eigen::Vector3d>& points, double resolution, int min_points,
                           double min_eigenvalue_ratio)
    : resolution_(resolution) {
  // Gather the points per cell in input order (serial: the sums, hence the
  // Gaussians, are the same bits on every run).
  std::unordered_map<std::int64_t, int> slot;
  std::vector<Eigen::Vector3i> keys;
  std::vector<std::vector<int>> members;
  std::vector<Eigen::Vector3i> cell_keys;  // per kept cell
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3i c = cellOf(points[i]);
    if (!inRange(c))
      throw InputError("target cloud", "point " + std::to_string(i),
                       "more than 2^20 cells of " + std::to_string(resolution) + " m from the origin");
    const auto [it, added] = slot.emplace(pack(c), static_cast<int>(keys.size()));
    if (added) {
      keys.push_back(c);
      members.emplace_back();
    }
    members[static_cast<std::size_t>(it->second)].push_back(static_cast<int>(i));
  }
  for (std::size_t s = 0; s < keys.size(); ++s) {
    const std::vector<int>& m = members[s];
    if (static_cast<int>(m.size()) < std::max(min_points, 3)) continue;
    // Shift by the first point so the sums stay small (cells far from the origin).
    const Eigen::Vector3d origin = points[static_cast<std::size_t>(m.front())];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    for (int j : m) {
      const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - origin;
      sum += d;
      outer.noalias() += d * d.transpose();
    }
    const double n = static_cast<double>(m.size());
    const Eigen::Vector3d mean_offset = sum / n;
    const Eigen::Matrix3d covariance = (outer - n * mean_offset * mean_offset.transpose()) / (n - 1.0);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
    Eigen::Vector3d values = eigen.eigenvalues();
    const double largest = values.maxCoeff();
    if (!(largest > 0) || !std::isfinite(largest)) continue;  // coincident points: no shape at all
    values = values.cwiseMax(min_eigenvalue_ratio * largest);
    NdtCell cell;
    cell.mean = origin + mean_offset;
    cell.inverse_covariance = eigen.eigenvectors() * values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
    cell.count = static_cast<int>(m.size());
    index_.emplace(pack(keys[s]), static_cast<int>(cells_.size()));
    cell_keys.push_back(keys[s]);
    cells_.push_back(cell);
  }
  if (cells_.empty())
    throw InputError("target cloud", "",
                     "no cell of " + std::to_string(resolution) + " m holds " + std::to_string(std::max(min_points, 3)) +
                         " points or more; the cloud is too sparse for this resolution");
  Eigen::Vector3i lo = cell_keys.front(), hi = cell_keys.front();
  for (const Eigen::Vector3i& c : cell_keys) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const Eigen::Vector3i size = hi - lo + Eigen::Vector3i::Ones();
  const double entries = double(size(0)) * double(size(1)) * double(size(2));
  // A table of 4-byte entries costs about what a hash of ~48-byte nodes
  // does when it is at most ~12 times fuller; up to 64 times (a view's
  // surface in its box at the finest level) it is kept for the speed, a
  // sparser or larger box gets the hash.
  const double cells = static_cast<double>(cell_keys.size());
  if (entries <= kMaxDenseEntries && entries <= std::max(65536.0, 64.0 * cells)) {
    dense_origin_ = lo;
    dense_size_ = size;
    dense_.assign(static_cast<std::size_t>(entries), -1);
    for (std::size_t k = 0; k < cell_keys.size(); ++k) {
      const Eigen::Vector3i d = cell_keys[k] - lo;
      dense_[denseSlot(d)] = static_cast<int>(k);
    }
    std::unordered_map<std::int64_t, int>().swap(index_);
  }
}

void NdtVoxelGrid::lookup(const Eigen::Vector3d& point, NdtNeighbourhood neighbourhood, std::vector<int>& out) const {
  out.clear();
  const Eigen::Vector3i c = cellOf(point);
  auto add = [&](int dx, int dy, int dz) {
    const int i = find(c + Eigen::Vector3i(dx, dy, dz));
    if (i >= 0) out.push_back(i);
  };
  switch (neighbourhood) {
    case NdtNeighbourhood::Single:
      add(0, 0, 0);
      break;
    case NdtNeighbourhood::Face7:
      add(0, 0, 0);
      add(-1, 0, 0);
      add(1, 0, 0);
      add(0, -1, 0);
      add(0, 1, 0);
      add(0, 0, -1);
      add(0, 0, 1);
      break;
    case NdtNeighbourhood::All27:
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) add(dx, dy, dz);
      break;
  }
}

}  // namespace icrkit::ndt
