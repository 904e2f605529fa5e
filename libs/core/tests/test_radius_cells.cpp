#include <icrkit/core/morton_order.hpp>
#include <icrkit/core/radius_cells.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

namespace icrkit {
namespace {

// The points of the cubes around cube c.
std::set<std::size_t> pointsAround(const RadiusCells& cells, std::size_t c) {
  std::vector<std::size_t> around;
  cells.neighbourCells(c, around);
  EXPECT_LE(around.size(), 27u);
  EXPECT_NE(std::find(around.begin(), around.end(), c), around.end());
  std::set<std::size_t> near;
  for (std::size_t cube : around) near.insert(cells.cellBegin(cube), cells.cellEnd(cube));
  return near;
}

// Every point's neighbours within the radius, found through the cubes,
// equal the brute-force answer; each point lies in exactly one cube.
TEST(RadiusCells, NeighbourCubesHoldEveryPointWithinTheRadius) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-0.05, 0.05);
  std::vector<Eigen::Vector3d> points(3000);
  for (auto& p : points) p = Eigen::Vector3d(coord(rng), coord(rng), 0.3 * coord(rng));
  points.push_back(points[10]);  // a duplicate
  const double radius = 0.012;
  const RadiusCells cells(points, radius);
  std::vector<int> seen(points.size(), 0);
  for (std::size_t c = 0; c < cells.cellCount(); ++c) {
    ASSERT_TRUE(std::is_sorted(cells.cellBegin(c), cells.cellEnd(c)));
    const std::set<std::size_t> candidates = pointsAround(cells, c);
    for (const std::uint32_t* it = cells.cellBegin(c); it != cells.cellEnd(c); ++it) {
      ++seen[*it];
      // The point lies in its cube's box.
      const Eigen::Vector3d min = cells.cellMin(c);
      EXPECT_TRUE((points[*it].array() >= min.array() - 1e-12).all()) << *it;
      EXPECT_TRUE((points[*it].array() <= min.array() + cells.edge() + 1e-12).all()) << *it;
      for (std::size_t j = 0; j < points.size(); ++j)
        if ((points[j] - points[*it]).norm() <= radius) {
          EXPECT_TRUE(candidates.count(j)) << *it << " " << j;
        }
    }
  }
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_EQ(seen[i], 1) << i;
}

// Lattice points built by adding the spacing again and again, the radius
// equal to the spacing: neighbours exactly one radius apart, whose cube
// coordinates round either way.
TEST(RadiusCells, NeighboursExactlyOneRadiusApartAreFound) {
  for (int start = 0; start < 20; ++start) {
    const double spacing = 0.0011 + 1e-5 * start;
    std::vector<Eigen::Vector3d> points;
    double x = 0.0371 * start;
    for (int k = 0; k < 200; ++k, x += spacing) points.emplace_back(x, 0.5 * x, -x);
    const double radius = (points[1] - points[0]).norm();
    const RadiusCells cells(points, radius);
    for (std::size_t c = 0; c < cells.cellCount(); ++c) {
      const std::set<std::size_t> near = pointsAround(cells, c);
      for (const std::uint32_t* it = cells.cellBegin(c); it != cells.cellEnd(c); ++it)
        for (std::size_t j = 0; j < points.size(); ++j)
          if ((points[j] - points[*it]).norm() <= radius) {
            EXPECT_TRUE(near.count(j)) << start << ": " << *it << " " << j;
          }
    }
  }
}

TEST(RadiusCells, RejectsBadInput) {
  const std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
  EXPECT_THROW(RadiusCells(points, 0.0), std::invalid_argument);
  EXPECT_THROW(RadiusCells(points, -1.0), std::invalid_argument);
  EXPECT_THROW(RadiusCells({Eigen::Vector3d(0, std::nan(""), 0)}, 1.0), std::invalid_argument);
  EXPECT_EQ(RadiusCells({}, 1.0).cellCount(), 0u);
}

// 1 km apart with a 0.1 mm radius, beyond 2^21 cubes per axis: larger
// cubes, the same guarantee.
TEST(RadiusCells, CloudsWiderThanTheCodeRangeGetLargerCubes) {
  const std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero(), Eigen::Vector3d(5e-5, 0, 0),
                                            Eigen::Vector3d(1000, 0, 0), Eigen::Vector3d(1000, 5e-5, 0)};
  const RadiusCells cells(points, 1e-4);
  EXPECT_GT(cells.edge(), 1e-4);
  for (std::size_t c = 0; c < cells.cellCount(); ++c) {
    const std::set<std::size_t> near = pointsAround(cells, c);
    for (const std::uint32_t* it = cells.cellBegin(c); it != cells.cellEnd(c); ++it)
      EXPECT_TRUE(near.count(*it ^ 1u)) << *it;  // 0 with 1, 2 with 3
  }
}

TEST(MortonOrder, NeighboursInSpaceAreNeighboursInOrder) {
  // A 16 x 16 x 16 lattice: Z-order visits each 2 x 2 x 2 block in 8 steps.
  std::vector<Eigen::Vector3d> points;
  for (int z = 0; z < 16; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) points.emplace_back(x, y, z);
  const std::vector<std::uint32_t> order = mortonOrder(points);
  ASSERT_EQ(order.size(), points.size());
  for (std::size_t k = 0; k < order.size(); k += 8) {
    Eigen::Vector3d lo = points[order[k]], hi = lo;
    for (std::size_t m = k; m < k + 8; ++m) {
      lo = lo.cwiseMin(points[order[m]]);
      hi = hi.cwiseMax(points[order[m]]);
    }
    EXPECT_EQ(hi - lo, Eigen::Vector3d::Ones()) << k;
  }
}

}  // namespace
}  // namespace icrkit
