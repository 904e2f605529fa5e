#include <icrkit/core/triangle_distance.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace icrkit {
namespace {

// The returned point must be the barycentric combination it claims, inside
// the triangle, at the claimed distance.
void expectConsistent(const TrianglePoint& r, const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                      const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  EXPECT_GE(r.u, 0.0);
  EXPECT_GE(r.v, 0.0);
  EXPECT_LE(r.u + r.v, 1.0 + 1e-15);
  const double scale = std::max({a.norm(), b.norm(), c.norm(), 1.0});
  EXPECT_LE(((1 - r.u - r.v) * a + r.u * b + r.v * c - r.point).norm(), 1e-14 * scale);
  EXPECT_DOUBLE_EQ(r.distance, (p - r.point).norm());
}

TEST(TriangleDistance, KnownRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  struct Case {
    Eigen::Vector3d p, expected;
  };
  const Case cases[] = {
      {{0.5, 0.5, 3.0}, {0.5, 0.5, 0.0}},     // above the interior
      {{0.5, 0.5, -0.25}, {0.5, 0.5, 0.0}},   // below it
      {{0.5, 0.5, 0.0}, {0.5, 0.5, 0.0}},     // on it
      {{-1.0, -1.0, 1.0}, a},                 // beyond corner a
      {{3.0, -0.5, 0.0}, b},                  // beyond corner b
      {{-0.1, 5.0, 2.0}, c},                  // beyond corner c
      {{1.0, -2.0, 1.0}, {1.0, 0.0, 0.0}},    // beyond edge ab
      {{-3.0, 1.5, 0.0}, {0.0, 1.5, 0.0}},    // beyond edge ac
      {{2.0, 2.0, -1.0}, {1.0, 1.0, 0.0}},    // beyond edge bc
      {{1.0, 1.0, 0.0}, {1.0, 1.0, 0.0}},     // on edge bc
  };
  for (const Case& k : cases) {
    const TrianglePoint r = closestPointOnTriangle(k.p, a, b, c);
    EXPECT_TRUE(r.point.isApprox(k.expected, 1e-15) || (r.point - k.expected).norm() < 1e-15)
        << k.p.transpose() << " -> " << r.point.transpose();
    EXPECT_NEAR(r.distance, (k.p - k.expected).norm(), 1e-15);
    expectConsistent(r, k.p, a, b, c);
  }
  // Barycentrics of a known interior point: (0.5, 0.5) = 0.25 b + 0.25 c.
  const TrianglePoint inside = closestPointOnTriangle({0.5, 0.5, 1.0}, a, b, c);
  EXPECT_NEAR(inside.u, 0.25, 1e-15);
  EXPECT_NEAR(inside.v, 0.25, 1e-15);
  // At a corner the barycentrics pick that corner.
  const TrianglePoint at_c = closestPointOnTriangle({-1.0, 3.0, 0.0}, a, b, c);
  EXPECT_NEAR(at_c.u, 0.0, 1e-15);
  EXPECT_NEAR(at_c.v, 1.0, 1e-15);
}

TEST(TriangleDistance, DegenerateTriangles) {
  // Collinear corners: the triangle is the segment from (0,0,0) to (3,0,0),
  // with b in between.
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(3, 0, 0);
  TrianglePoint r = closestPointOnTriangle({2.0, 1.0, 0.0}, a, b, c);
  EXPECT_NEAR(r.distance, 1.0, 1e-15);
  EXPECT_TRUE(r.point.isApprox(Eigen::Vector3d(2, 0, 0), 1e-15));
  expectConsistent(r, {2.0, 1.0, 0.0}, a, b, c);
  r = closestPointOnTriangle({4.0, 0.0, 0.0}, a, b, c);
  EXPECT_NEAR(r.distance, 1.0, 1e-15);
  r = closestPointOnTriangle({-2.0, 0.0, 0.0}, a, b, c);
  EXPECT_NEAR(r.distance, 2.0, 1e-15);

  // Two coincident corners: a segment.
  r = closestPointOnTriangle({0.5, 2.0, 0.0}, a, a, b);
  EXPECT_NEAR(r.distance, 2.0, 1e-15);
  EXPECT_TRUE(r.point.isApprox(Eigen::Vector3d(0.5, 0, 0), 1e-15));
  expectConsistent(r, {0.5, 2.0, 0.0}, a, a, b);

  // All three coincident: a point.
  const Eigen::Vector3d q(1, 2, 3);
  r = closestPointOnTriangle({1, 2, 5}, q, q, q);
  EXPECT_NEAR(r.distance, 2.0, 1e-15);
  EXPECT_EQ(r.point, q);
  EXPECT_TRUE(std::isfinite(r.u) && std::isfinite(r.v));
}

// Brute force: the distance to a fine barycentric grid of the triangle is an
// upper bound of the true distance, and exceeds it by at most the distance
// from the true closest point to the grid: under two steps of the longest edge.
TEST(TriangleDistance, AgreesWithBruteForce) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  auto randomPoint = [&] { return Eigen::Vector3d(coord(rng), coord(rng), coord(rng)); };
  constexpr int kSteps = 200;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3d a = randomPoint();
    Eigen::Vector3d b = randomPoint(), c = randomPoint();
    if (trial % 10 == 0) c = a + 0.7 * (b - a);  // collinear
    if (trial % 10 == 1) c = b + 1e-9 * randomPoint();  // sliver
    // Queries: random, far away, and right on or near the plane.
    Eigen::Vector3d p = 2.0 * randomPoint();
    if (trial % 3 == 1) p = 10.0 * randomPoint();
    if (trial % 3 == 2) p = a + 0.3 * (b - a) + 0.4 * (c - a) + 1e-3 * randomPoint();

    const TrianglePoint r = closestPointOnTriangle(p, a, b, c);
    expectConsistent(r, p, a, b, c);
    double grid = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        grid = std::min(grid, (p - ((1 - u - v) * a + u * b + v * c)).norm());
      }
    const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
    EXPECT_LE(r.distance, grid + 1e-12) << "trial " << trial;
    EXPECT_GE(r.distance, grid - 2.0 * longest / kSteps) << "trial " << trial;
  }
}

}  // namespace
}  // namespace icrkit
