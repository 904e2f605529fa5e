#pragma once
/// \file
/// Nearest-neighbour and radius queries over a fixed set of 3D points
/// (nanoflann underneath). Queries are const and thread-safe.

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <vector>

namespace icrkit {

struct Neighbour {
  std::size_t index;
  double distance;  ///< Euclidean, metres
};

class KdTree {
public:
  /// Keeps a reference to `points`: they must outlive the tree, unchanged.
  explicit KdTree(const std::vector<Eigen::Vector3d>& points, std::size_t leaf_size = 10);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  std::size_t size() const;

  /// The k nearest points, nearest first (fewer when the set is smaller).
  std::vector<Neighbour> nearest(const Eigen::Vector3d& query, std::size_t k) const;
  /// All points with distance <= radius, nearest first.
  std::vector<Neighbour> withinRadius(const Eigen::Vector3d& query, double radius) const;
  /// Indices of all points with distance <= radius, ascending, written into
  /// `out` (cleared first; its capacity is reused, so a loop that keeps one
  /// vector per thread does not allocate once the vector is large enough).
  void indicesWithinRadius(const Eigen::Vector3d& query, double radius, std::vector<std::size_t>& out) const;
  /// The same in the order the tree visits them: not sorted, but fixed for a
  /// given point set and query, whatever the thread count (the tree is built
  /// serially); saves the sort where only that determinism is needed.
  void indicesWithinRadiusInTreeOrder(const Eigen::Vector3d& query, double radius,
                                      std::vector<std::size_t>& out) const;
  /// The index of the nearest point closer than `max_distance`, or -1. The
  /// bound prunes the search from the start (an ICP's pairing distance),
  /// and nothing is allocated; ties go to the lower index.
  long nearestWithin(const Eigen::Vector3d& query, double max_distance) const;
  /// Number of points with distance <= radius.
  std::size_t countWithinRadius(const Eigen::Vector3d& query, double radius) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct SpacingStatistics {
  double mean = 0.0;    ///< mean distance to the nearest other point (m)
  double median = 0.0;  ///< median of the same
};

/// Nearest-neighbour spacing of a point set (0 for fewer than two points);
/// coincident duplicates count with distance 0.
SpacingStatistics nearestNeighbourSpacing(const std::vector<Eigen::Vector3d>& points);

/// Each point's distance to the nearest other point (0 for a duplicate,
/// infinity for a lone point), computed in parallel.
std::vector<double> nearestNeighbourDistances(const std::vector<Eigen::Vector3d>& points);
/// The same with a tree already built over `points`.
std::vector<double> nearestNeighbourDistances(const std::vector<Eigen::Vector3d>& points, const KdTree& tree);
/// Mean and median of such distances (0 for fewer than two).
SpacingStatistics spacingStatistics(std::vector<double> distances);

}  // namespace icrkit
