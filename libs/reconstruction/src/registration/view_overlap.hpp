#pragma once
/// \file
/// Which views touch the others: the share of a view's occupied cubes
/// that other views occupy too, with the views placed by their poses.
///
/// Why cubes and not a nearest-neighbour search: the test runs on every
/// registration, and a view that ended a centimetre or more off the others
/// is what it must find. Such a view's surface crosses theirs along a line
/// and shares a few percent of its 4 mm cubes; a view in place shares most
/// of them with the others and a third or more with its nearest neighbour
/// (on the real PrimeSense views: 0.05-0.10 against 0.64-0.99, at 9 to 18
/// views). Views can also be off together, agreeing with each other but
/// not with the rest (two Stanford scans of the bunny's back, 22 mm off;
/// half of nine views turned against the other half): the pairs then fall
/// apart into groups (docs/reconstruction.md, "Stop 53").

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <unordered_set>
#include <vector>

namespace icrkit::reconstruction {

/// The keys (cube_key.hpp) of the cubes of edge `cube` (metres) that
/// `points`, placed by `pose`, occupy: sorted, each once.
std::vector<std::int64_t> occupiedCubeKeys(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose,
                                           double cube);

struct CubeOverlap {
  /// Per view, the share (0-1) of the cubes its points occupy that some
  /// other view occupies as well; 0 for a view without points.
  std::vector<double> shared;
  /// pair(i, j): the share of view i's cubes that view j occupies.
  Eigen::MatrixXd pair;
};

/// The overlap of views, cubes of edge `cube` (metres). `points` per view in
/// its sensor frame, `poses` sensor to world.
CubeOverlap cubeOverlap(const std::vector<std::vector<Eigen::Vector3d>>& points,
                        const std::vector<Eigen::Isometry3d>& poses, double cube);

/// The groups `views` fall into when two views are linked by sharing at
/// least `min_share` of either one's cubes (`pair` of cubeOverlap), and
/// linked views of linked views go together: each group and the groups
/// in the order of `views`.
std::vector<std::vector<std::size_t>> linkedGroups(const Eigen::MatrixXd& pair, const std::vector<std::size_t>& views,
                                                   double min_share);

/// The views of the largest linked group of all views (ties: the group
/// holding the lowest view index); 1 for those, 0 else.
std::vector<std::uint8_t> largestLinkedGroup(const Eigen::MatrixXd& pair, double min_share);

/// The cubes some views occupy, to test another view against.
class OccupiedCubes {
 public:
  explicit OccupiedCubes(double cube) : cube_(cube) {}
  void add(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose);
  /// Share of the cubes `points` (placed by `pose`) occupy that are
  /// occupied here; 0 for no points.
  double shareOf(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) const;

 private:
  double cube_;
  std::unordered_set<std::int64_t> keys_;
};

}  // namespace icrkit::reconstruction
