// Which views touch the others (registration/view_overlap.hpp): the share
// of a view's occupied cubes another view occupies, on surfaces with known
// answers.

#include "registration/view_overlap.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace icrkit::reconstruction {
namespace {

// A 10 cm square of the plane x = 0.5 (a camera's view of a wall), 1 mm
// spacing, in the sensor frame.
std::vector<Eigen::Vector3d> wall() {
  std::vector<Eigen::Vector3d> points;
  for (int y = -50; y < 50; ++y)
    for (int z = -50; z < 50; ++z) points.emplace_back(0.5, 0.001 * y + 0.0005, 0.001 * z + 0.0005);
  return points;
}

Eigen::Isometry3d shifted(const Eigen::Vector3d& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = t;
  return pose;
}

TEST(ViewOverlap, ViewsOnTheSameSurfaceShareEveryCube) {
  const std::vector<std::vector<Eigen::Vector3d>> views{wall(), wall(), wall()};
  const std::vector<Eigen::Isometry3d> poses(3, Eigen::Isometry3d::Identity());
  const CubeOverlap overlap = cubeOverlap(views, poses, 0.004);
  for (double share : overlap.shared) EXPECT_DOUBLE_EQ(share, 1.0);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(overlap.pair(i, j), i == j ? 0.0 : 1.0);
}

TEST(ViewOverlap, AViewOneCentimetreOffTheSurfaceSharesNone) {
  // Off along the wall's normal by 1 cm: its 4 mm cubes are two and a half
  // cubes behind the others'.
  const std::vector<std::vector<Eigen::Vector3d>> views{wall(), wall(), wall()};
  const std::vector<Eigen::Isometry3d> poses{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                                             shifted({0.01, 0.0, 0.0})};
  const std::vector<double> shares = cubeOverlap(views, poses, 0.004).shared;
  EXPECT_DOUBLE_EQ(shares[0], 1.0);
  EXPECT_DOUBLE_EQ(shares[1], 1.0);
  EXPECT_DOUBLE_EQ(shares[2], 0.0);
}

TEST(ViewOverlap, HalfAViewSlidAlongTheSurfaceSharesHalf) {
  // Slid 5 cm along the wall (y): half its cubes (12.5 of 25 columns, cut
  // at a cube boundary: 12 or 13) lie over the other view.
  const std::vector<std::vector<Eigen::Vector3d>> views{wall(), wall()};
  const std::vector<Eigen::Isometry3d> poses{Eigen::Isometry3d::Identity(), shifted({0.0, 0.048, 0.0})};
  const CubeOverlap overlap = cubeOverlap(views, poses, 0.004);
  EXPECT_NEAR(overlap.shared[0], 0.5, 0.05);
  EXPECT_NEAR(overlap.shared[1], 0.5, 0.05);
  EXPECT_DOUBLE_EQ(overlap.pair(0, 1), overlap.shared[0]);
  EXPECT_DOUBLE_EQ(overlap.pair(1, 0), overlap.shared[1]);
}

TEST(ViewOverlap, AViewWithoutPointsSharesNothing) {
  const std::vector<std::vector<Eigen::Vector3d>> views{wall(), {}};
  const std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  const std::vector<double> shares = cubeOverlap(views, poses, 0.004).shared;
  EXPECT_DOUBLE_EQ(shares[0], 0.0);  // no other view
  EXPECT_DOUBLE_EQ(shares[1], 0.0);
}

TEST(ViewOverlap, TwoViewsOffTogetherFallOutsideTheLargestLinkedGroup) {
  // Views 0-2 on the wall, views 3 and 4 on it 1 cm behind: each pair
  // within a group shares every cube, across the groups none.
  const std::vector<std::vector<Eigen::Vector3d>> views(5, wall());
  const Eigen::Isometry3d home = Eigen::Isometry3d::Identity(), off = shifted({0.01, 0.0, 0.0});
  const CubeOverlap overlap = cubeOverlap(views, {home, home, home, off, off}, 0.004);
  for (double share : overlap.shared) EXPECT_DOUBLE_EQ(share, 1.0);  // each has a partner
  EXPECT_EQ(largestLinkedGroup(overlap.pair, 0.15), (std::vector<std::uint8_t>{1, 1, 1, 0, 0}));
  // Among some of the views only: who goes with whom.
  EXPECT_EQ(linkedGroups(overlap.pair, {1, 3, 4}, 0.15), (std::vector<std::vector<std::size_t>>{{1}, {3, 4}}));
  EXPECT_EQ(linkedGroups(overlap.pair, {4, 0, 3}, 0.15), (std::vector<std::vector<std::size_t>>{{4, 3}, {0}}));
  // Two against two: the group holding view 0 is taken.
  const CubeOverlap even = cubeOverlap({wall(), wall(), wall(), wall()}, {off, home, off, home}, 0.004);
  EXPECT_EQ(largestLinkedGroup(even.pair, 0.15), (std::vector<std::uint8_t>{1, 0, 1, 0}));
}

TEST(ViewOverlap, AChainOfOverlappingViewsIsOneGroup) {
  // Each view slid 6 cm along the wall from the last: neighbours share
  // about 0.4 of their cubes, views two apart none; linked through the chain.
  std::vector<std::vector<Eigen::Vector3d>> views(4, wall());
  std::vector<Eigen::Isometry3d> poses;
  for (int v = 0; v < 4; ++v) poses.push_back(shifted({0.0, 0.06 * v, 0.0}));
  const CubeOverlap overlap = cubeOverlap(views, poses, 0.004);
  EXPECT_NEAR(overlap.pair(0, 1), 0.4, 0.05);
  EXPECT_DOUBLE_EQ(overlap.pair(0, 2), 0.0);
  EXPECT_EQ(largestLinkedGroup(overlap.pair, 0.15), (std::vector<std::uint8_t>(4, 1)));
  EXPECT_EQ(largestLinkedGroup(overlap.pair, 0.5), (std::vector<std::uint8_t>{1, 0, 0, 0}));
}

TEST(ViewOverlap, OccupiedCubesTestAViewAgainstOthersOnly) {
  OccupiedCubes others(0.004);
  others.add(wall(), Eigen::Isometry3d::Identity());
  EXPECT_DOUBLE_EQ(others.shareOf(wall(), Eigen::Isometry3d::Identity()), 1.0);
  EXPECT_DOUBLE_EQ(others.shareOf(wall(), shifted({0.01, 0.0, 0.0})), 0.0);
  EXPECT_DOUBLE_EQ(others.shareOf({}, Eigen::Isometry3d::Identity()), 0.0);
}

}  // namespace
}  // namespace icrkit::reconstruction
