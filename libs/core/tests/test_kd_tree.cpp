#include <icrkit/core/kd_tree.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace icrkit {
namespace {

// Points (i, j, k) * step for i, j, k in [0, n).
std::vector<Eigen::Vector3d> grid(int n, double step) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) points.emplace_back(i * step, j * step, k * step);
  return points;
}

std::vector<Eigen::Vector3d> randomPoints(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points(count);
  for (auto& p : points) p = Eigen::Vector3d(coord(rng), coord(rng), coord(rng));
  return points;
}

TEST(KdTree, EmptySetAnswersNothing) {
  const std::vector<Eigen::Vector3d> points;
  const KdTree tree(points);
  EXPECT_EQ(tree.size(), 0u);
  EXPECT_TRUE(tree.nearest(Eigen::Vector3d::Zero(), 3).empty());
  EXPECT_TRUE(tree.withinRadius(Eigen::Vector3d::Zero(), 10.0).empty());
  EXPECT_EQ(tree.countWithinRadius(Eigen::Vector3d::Zero(), 10.0), 0u);
}

TEST(KdTree, NearestOnGridGivesKnownDistances) {
  const double step = 0.5;
  const auto points = grid(5, step);
  const KdTree tree(points);
  ASSERT_EQ(tree.size(), 125u);

  // The centre grid point (2,2,2): itself, then its 6 face neighbours at
  // one step, then the 12 edge neighbours at sqrt(2) steps.
  const Eigen::Vector3d centre(1.0, 1.0, 1.0);
  const auto nearest = tree.nearest(centre, 19);
  ASSERT_EQ(nearest.size(), 19u);
  EXPECT_EQ(points[nearest[0].index], centre);
  EXPECT_DOUBLE_EQ(nearest[0].distance, 0.0);
  for (std::size_t i = 1; i <= 6; ++i) EXPECT_NEAR(nearest[i].distance, step, 1e-12) << i;
  for (std::size_t i = 7; i < 19; ++i) EXPECT_NEAR(nearest[i].distance, step * std::sqrt(2.0), 1e-12) << i;
  for (const auto& nb : nearest) EXPECT_NEAR((points[nb.index] - centre).norm(), nb.distance, 1e-12);

  // Off-grid query: nearest corner of the enclosing cell.
  const auto one = tree.nearest(Eigen::Vector3d(0.1, 0.2, 0.05), 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(points[one[0].index], Eigen::Vector3d(0.0, 0.0, 0.0));
  EXPECT_NEAR(one[0].distance, std::sqrt(0.01 + 0.04 + 0.0025), 1e-12);
}

TEST(KdTree, NearestReturnsFewerWhenSetIsSmall) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}};
  const KdTree tree(points);
  const auto nearest = tree.nearest(Eigen::Vector3d(0.9, 0, 0), 5);
  ASSERT_EQ(nearest.size(), 2u);
  EXPECT_EQ(nearest[0].index, 1u);
  EXPECT_NEAR(nearest[0].distance, 0.1, 1e-12);
  EXPECT_EQ(nearest[1].index, 0u);
  EXPECT_NEAR(nearest[1].distance, 0.9, 1e-12);
  EXPECT_TRUE(tree.nearest(Eigen::Vector3d::Zero(), 0).empty());
}

TEST(KdTree, RadiusIsInclusiveAndEuclidean) {
  const auto points = grid(5, 1.0);
  const KdTree tree(points);
  const Eigen::Vector3d centre(2, 2, 2);
  // Exactly one step: itself and the 6 face neighbours (distance == radius counts).
  EXPECT_EQ(tree.countWithinRadius(centre, 1.0), 7u);
  const auto within = tree.withinRadius(centre, 1.0);
  ASSERT_EQ(within.size(), 7u);
  EXPECT_DOUBLE_EQ(within[0].distance, 0.0);
  for (std::size_t i = 1; i < within.size(); ++i) EXPECT_DOUBLE_EQ(within[i].distance, 1.0);
  // Just under sqrt(2) keeps the edge neighbours out, just over lets all 12 in.
  EXPECT_EQ(tree.countWithinRadius(centre, 1.41), 7u);
  EXPECT_EQ(tree.countWithinRadius(centre, 1.42), 19u);
  EXPECT_EQ(tree.countWithinRadius(centre, -1.0), 0u);
}

TEST(KdTree, AgreesWithBruteForceOnRandomPoints) {
  const auto points = randomPoints(2000, 12345);
  const KdTree tree(points, 7);
  const auto queries = randomPoints(200, 777);
  for (const double radius : {0.05, 0.2, 0.6}) {
    for (const auto& q : queries) {
      std::vector<std::pair<double, std::size_t>> expected;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = (points[i] - q).norm();
        if (d <= radius) expected.emplace_back(d, i);
      }
      std::sort(expected.begin(), expected.end());
      ASSERT_EQ(tree.countWithinRadius(q, radius), expected.size());
      std::vector<std::size_t> ascending, tree_order, again;
      tree.indicesWithinRadius(q, radius, ascending);
      tree.indicesWithinRadiusInTreeOrder(q, radius, tree_order);
      tree.indicesWithinRadiusInTreeOrder(q, radius, again);
      EXPECT_TRUE(std::is_sorted(ascending.begin(), ascending.end()));
      EXPECT_EQ(tree_order, again);  // the same order on every call
      std::sort(tree_order.begin(), tree_order.end());
      EXPECT_EQ(tree_order, ascending);
      const auto within = tree.withinRadius(q, radius);
      ASSERT_EQ(within.size(), expected.size());
      for (std::size_t i = 0; i < within.size(); ++i) {
        EXPECT_EQ(within[i].index, expected[i].second);
        EXPECT_NEAR(within[i].distance, expected[i].first, 1e-12);
      }
    }
  }
  for (const auto& q : queries) {
    std::vector<double> all;
    for (const auto& p : points) all.push_back((p - q).norm());
    std::sort(all.begin(), all.end());
    const auto nearest = tree.nearest(q, 8);
    ASSERT_EQ(nearest.size(), 8u);
    for (std::size_t i = 0; i < nearest.size(); ++i) EXPECT_NEAR(nearest[i].distance, all[i], 1e-12);
  }
}

TEST(KdTree, SurvivesMove) {
  const auto points = grid(3, 1.0);
  KdTree tree(points);
  KdTree moved(std::move(tree));
  EXPECT_EQ(moved.size(), 27u);
  EXPECT_EQ(moved.countWithinRadius(Eigen::Vector3d(1, 1, 1), 1.0), 7u);
}

TEST(NearestNeighbourSpacing, RegularGridGivesItsStep) {
  const auto stats = nearestNeighbourSpacing(grid(6, 0.25));
  EXPECT_NEAR(stats.mean, 0.25, 1e-12);
  EXPECT_NEAR(stats.median, 0.25, 1e-12);
}

TEST(NearestNeighbourSpacing, DuplicatesCountAsZero) {
  // Three points on a line one metre apart plus a duplicate of the first:
  // spacings 0, 0, 1, 1 -> mean 0.5, median 0.5 (mean of the middle two).
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}};
  const auto stats = nearestNeighbourSpacing(points);
  EXPECT_DOUBLE_EQ(stats.mean, 0.5);
  EXPECT_DOUBLE_EQ(stats.median, 0.5);

  // Many copies of one point: every point has a coincident neighbour.
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(3, 4, 5));
  const auto zero = nearestNeighbourSpacing(same);
  EXPECT_EQ(zero.mean, 0.0);
  EXPECT_EQ(zero.median, 0.0);
}

TEST(NearestNeighbourSpacing, OddCountMedianAndTinySets) {
  // Spacings 1, 1, 2 -> median 1, mean 4/3.
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {3, 0, 0}};
  const auto stats = nearestNeighbourSpacing(points);
  EXPECT_DOUBLE_EQ(stats.median, 1.0);
  EXPECT_NEAR(stats.mean, 4.0 / 3.0, 1e-15);

  EXPECT_EQ(nearestNeighbourSpacing({}).mean, 0.0);
  const auto single = nearestNeighbourSpacing({Eigen::Vector3d(1, 2, 3)});
  EXPECT_EQ(single.mean, 0.0);
  EXPECT_EQ(single.median, 0.0);
}

TEST(NearestNeighbourSpacing, MatchesBruteForceOnRandomPoints) {
  const auto points = randomPoints(3000, 4242);  // enough to run in several TBB chunks
  std::vector<double> expected(points.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = 0; j < points.size(); ++j)
      if (i != j) expected[i] = std::min(expected[i], (points[i] - points[j]).norm());
  double sum = 0.0;
  for (double d : expected) sum += d;
  std::sort(expected.begin(), expected.end());
  const auto stats = nearestNeighbourSpacing(points);
  EXPECT_NEAR(stats.mean, sum / points.size(), 1e-12);
  EXPECT_NEAR(stats.median, 0.5 * (expected[1499] + expected[1500]), 1e-12);
  // Bit-identical on one thread: the summation order does not follow the threads.
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const auto serial = nearestNeighbourSpacing(points);
  EXPECT_EQ(serial.mean, stats.mean);
  EXPECT_EQ(serial.median, stats.median);
}

}  // namespace
}  // namespace icrkit

namespace icrkit {
namespace {

TEST(KdTree, NearestNeighbourDistancesPerPoint) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {0.5, 0, 0}, {2, 0, 0}, {2, 0, 0}};
  const std::vector<double> d = nearestNeighbourDistances(points);
  ASSERT_EQ(d.size(), 4u);
  EXPECT_DOUBLE_EQ(d[0], 0.5);
  EXPECT_DOUBLE_EQ(d[1], 0.5);
  EXPECT_DOUBLE_EQ(d[2], 0.0);  // duplicates
  EXPECT_DOUBLE_EQ(d[3], 0.0);
  const SpacingStatistics s = spacingStatistics(d);
  EXPECT_DOUBLE_EQ(s.mean, 0.25);
  EXPECT_DOUBLE_EQ(s.median, 0.25);
  EXPECT_TRUE(std::isinf(nearestNeighbourDistances({{1, 2, 3}})[0]));
}

}  // namespace
}  // namespace icrkit

namespace icrkit {
namespace {

TEST(KdTree, NearestWithinMatchesBruteForceAndHonoursTheBound) {
  std::vector<Eigen::Vector3d> points = randomPoints(500, 9);
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  points.push_back(points[17]);  // a duplicate: the lower index wins
  const KdTree tree(points);
  EXPECT_EQ(tree.nearestWithin(points[17], 0.01), 17);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d query(u(rng), u(rng), u(rng));
    const double bound = 0.05 + 0.2 * (q % 3);
    long best = -1;
    double best_d = bound;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double d = (points[i] - query).norm();
      if (d < best_d) { best_d = d; best = static_cast<long>(i); }
    }
    EXPECT_EQ(tree.nearestWithin(query, bound), best) << "query " << q;
  }
  EXPECT_EQ(tree.nearestWithin(Eigen::Vector3d(5, 5, 5), 1.0), -1);
  EXPECT_EQ(tree.nearestWithin(points[3], 0.0), -1);
  EXPECT_EQ(KdTree(std::vector<Eigen::Vector3d>{}).nearestWithin(Eigen::Vector3d::Zero(), 1.0), -1);
}

TEST(KdTree, NearestWithinGivesTheLowestIndexAmongEquallyNearPointsInAnyLeaf) {
  // Points 0..15 on a line; each midpoint is equally near two of them,
  // which small leaves put apart.
  std::vector<Eigen::Vector3d> points;
  for (int x = 0; x < 16; ++x) points.emplace_back(x, 0, 0);
  for (std::size_t leaf : {1u, 2u, 10u}) {
    const KdTree tree(points, leaf);
    for (int m = 0; m + 1 < 16; ++m)
      EXPECT_EQ(tree.nearestWithin(Eigen::Vector3d(m + 0.5, 0, 0), 2.0), m) << "leaf " << leaf << " midpoint " << m;
    // Beyond the bound's reach, and exactly at it: nothing.
    EXPECT_EQ(tree.nearestWithin(Eigen::Vector3d(3.5, 0, 0), 0.5), -1) << "leaf " << leaf;
  }
}

}  // namespace
}  // namespace icrkit
