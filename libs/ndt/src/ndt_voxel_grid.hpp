#pragma once
/// \file
/// The NDT voxel grid: one Gaussian (mean, regularised inverse covariance)
/// per cubic cell of the target cloud with enough points. Private to the
/// ndt library.

#include <icrkit/ndt/ndt_registration.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace icrkit::ndt {

struct NdtCell {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inverse_covariance = Eigen::Matrix3d::Zero();
  int count = 0;
};

class NdtVoxelGrid {
public:
  /// Cells are the half-open cubes [i r, (i+1) r) per axis, i an integer.
  /// Throws InputError when the cloud spans more than 2^20 cells along an
  /// axis or when no cell keeps a Gaussian.
  NdtVoxelGrid(const std::vector<Eigen::Vector3d>& points, double resolution, int min_points,
               double min_eigenvalue_ratio);

  double resolution() const { return resolution_; }
  std::size_t size() const { return cells_.size(); }
  const std::vector<NdtCell>& cells() const { return cells_; }

  /// Indices of the Gaussians the point is scored against, written into
  /// `out` (cleared first), in a fixed order; empty when none.
  void lookup(const Eigen::Vector3d& point, NdtNeighbourhood neighbourhood, std::vector<int>& out) const;

private:
  Eigen::Vector3i cellOf(const Eigen::Vector3d& point) const;
  int find(const Eigen::Vector3i& cell) const;
  // Position in dense_ of a cell's offset from dense_origin_ (inside the box).
  std::size_t denseSlot(const Eigen::Vector3i& offset) const;

  double resolution_;
  std::vector<NdtCell> cells_;
  // Position in cells_ per cell: a dense table over the occupied cells'
  // bounding box when it is small (an object's view: a few hundred
  // thousand cells; a lookup is then one load, not a hash probe), else a
  // hash of the packed coordinates.
  Eigen::Vector3i dense_origin_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i dense_size_ = Eigen::Vector3i::Zero();
  std::vector<int> dense_;
  std::unordered_map<std::int64_t, int> index_;
};

}  // namespace icrkit::ndt
