#include "meshing/hole_triangulation.hpp"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

namespace icrkit::reconstruction {
namespace {

std::vector<Eigen::Vector3d> regularPolygon(int n, double radius) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i)
    p.emplace_back(radius * std::cos(2 * M_PI * i / n), radius * std::sin(2 * M_PI * i / n), 0.0);
  return p;
}

const auto kAnyChord = [](int, int) { return true; };

TEST(HoleTriangulation, ConvexPolygonGetsNMinusTwoFacesAlongItsNormals) {
  for (int n : {3, 4, 6, 11, 40}) {
    const auto p = regularPolygon(n, 0.01);
    const std::vector<Eigen::Vector3d> up(p.size(), Eigen::Vector3d::UnitZ());
    const PolygonTriangulation t = triangulatePolygon(p, up, kAnyChord);
    ASSERT_TRUE(t.found) << n;
    ASSERT_EQ(t.triangles.size(), static_cast<std::size_t>(n - 2));
    double area = 0.0;
    std::set<std::pair<int, int>> directed;
    for (const auto& f : t.triangles) {
      const Eigen::Vector3d normal = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
      EXPECT_GT(normal.z(), 0.0);
      area += 0.5 * normal.norm();
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(directed.emplace(f[k], f[(k + 1) % 3]).second) << "edge used twice";
    }
    // The faces tile the polygon exactly: area n/2 r^2 sin(2 pi / n).
    EXPECT_NEAR(area, 0.5 * n * 1e-4 * std::sin(2 * M_PI / n), 1e-12) << n;
    // Every side appears once, in the polygon's own direction.
    for (int i = 0; i < n; ++i) EXPECT_EQ(directed.count({i, (i + 1) % n}), 1u) << n;
  }
}

TEST(HoleTriangulation, NormalsAgainstTheWindingLeaveNoFill) {
  const auto p = regularPolygon(5, 0.01);
  const std::vector<Eigen::Vector3d> down(p.size(), -Eigen::Vector3d::UnitZ());
  EXPECT_FALSE(triangulatePolygon(p, down, kAnyChord).found);
}

TEST(HoleTriangulation, AFoldedRimIsFilledOnlyWhenDisagreementIsAllowed) {
  // The rim of a hole the surface overlaps runs against its normals: no
  // face can agree, so the strict fill finds none; the tolerant one tiles
  // the polygon (it is the caller's job to check it lies on the surface).
  const auto p = regularPolygon(5, 0.01);
  const std::vector<Eigen::Vector3d> down(p.size(), -Eigen::Vector3d::UnitZ());
  const PolygonTriangulation t = triangulatePolygon(p, down, kAnyChord, FillFacing::prefer_agreeing);
  ASSERT_TRUE(t.found);
  EXPECT_EQ(t.triangles.size(), 3u);
  // A flat hole whose every possible face agrees: the same fill either way.
  const auto q = regularPolygon(7, 0.01);
  std::vector<Eigen::Vector3d> n;
  for (int i = 0; i < 7; ++i) n.emplace_back(0.3 * std::cos(i), 0.3 * std::sin(2 * i), 1.0);
  const PolygonTriangulation strict = triangulatePolygon(q, n, kAnyChord);
  const PolygonTriangulation tolerant = triangulatePolygon(q, n, kAnyChord, FillFacing::prefer_agreeing);
  ASSERT_TRUE(strict.found);
  ASSERT_TRUE(tolerant.found);
  EXPECT_EQ(strict.triangles, tolerant.triangles);
  // A bent quad whose smaller fill (diagonal 0-2, 1.40 against 1.45) has a
  // face against its corners' normals: the tolerant fill still takes the
  // agreeing diagonal 1-3, as the strict one must.
  const std::vector<Eigen::Vector3d> bent{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 2.1, -1}};
  const std::vector<Eigen::Vector3d> tipped{{0.8, -0.7, 0.3}, {0.3, 0, 0.2}, {0.1, -0.7, 0.6}, {-0.9, -0.5, 1.2}};
  for (const FillFacing facing : {FillFacing::agree, FillFacing::prefer_agreeing}) {
    const PolygonTriangulation t = triangulatePolygon(bent, tipped, kAnyChord, facing);
    ASSERT_TRUE(t.found);
    for (const auto& f : t.triangles) {
      const std::set<int> corners(f.begin(), f.end());
      EXPECT_TRUE(corners.count(1) && corners.count(3)) << "took the disagreeing diagonal 0-2";
    }
  }
}

TEST(HoleTriangulation, ForbiddenChordTakesTheOtherDiagonal) {
  // A square whose shorter diagonal (0, 2) is an edge elsewhere already.
  std::vector<Eigen::Vector3d> p{{0, 0, 0}, {1, 0, 0}, {1.2, 1.2, 0}, {0, 1, 0}};
  const std::vector<Eigen::Vector3d> up(p.size(), Eigen::Vector3d::UnitZ());
  const PolygonTriangulation free = triangulatePolygon(p, up, kAnyChord);
  ASSERT_TRUE(free.found);
  const PolygonTriangulation forced =
      triangulatePolygon(p, up, [](int a, int b) { return !(a == 0 && b == 2); });
  ASSERT_TRUE(forced.found);
  for (const auto& f : forced.triangles) {
    const std::set<int> corners(f.begin(), f.end());
    EXPECT_FALSE(corners.count(0) && corners.count(2)) << "used the forbidden chord";
  }
  // Both diagonals forbidden: no triangulation exists.
  EXPECT_FALSE(triangulatePolygon(p, up, [](int, int) { return false; }).found);
}

TEST(HoleTriangulation, PrefersTheFlatFillOfABentHole) {
  // A hexagon folded along the chord (0, 3): the least-area fill keeps
  // faces on either side of the fold and never spans across it.
  std::vector<Eigen::Vector3d> p{{0, 0, 0}, {1, -1, 0.3}, {2, -1, 0.3}, {3, 0, 0}, {2, 1, 0.3}, {1, 1, 0.3}};
  const std::vector<Eigen::Vector3d> up(p.size(), Eigen::Vector3d::UnitZ());
  const PolygonTriangulation t = triangulatePolygon(p, up, kAnyChord);
  ASSERT_TRUE(t.found);
  EXPECT_EQ(t.triangles.size(), 4u);
}

TEST(HoleTriangulation, DegenerateInput) {
  const std::vector<Eigen::Vector3d> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_FALSE(triangulatePolygon(two, two, kAnyChord).found);
  // Collinear corners have no face with an area.
  const std::vector<Eigen::Vector3d> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<Eigen::Vector3d> up(3, Eigen::Vector3d::UnitZ());
  EXPECT_FALSE(triangulatePolygon(line, up, kAnyChord).found);
}

}  // namespace
}  // namespace icrkit::reconstruction
