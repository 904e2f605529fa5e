#include <icrkit/core/mesh_distance.hpp>
#include <icrkit/core/mesh_primitives.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace icrkit {
namespace {

using test::unitCube;

// Two triangles over [x0,x1] x [y0,y1] with z = slope * x + height.
TriangleMesh square(double x0, double x1, double y0, double y1, double height, double slope = 0.0) {
  TriangleMesh mesh;
  for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}})
    mesh.vertices.positions.emplace_back(x, y, slope * x + height);
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TEST(MeshDistance, ParallelSquaresAreEverywhereTheGapApart) {
  const MeshDistanceStatistics s = meshDistance(square(0, 1, 0, 1, 0.0), square(0, 1, 0, 1, 0.25), {1000, 1});
  EXPECT_EQ(s.points, 4u + 1000u);
  EXPECT_NEAR(s.max, 0.25, 1e-15);
  EXPECT_NEAR(s.mean, 0.25, 1e-15);
  EXPECT_NEAR(s.rms, 0.25, 1e-15);
  EXPECT_NEAR(s.median, 0.25, 1e-15);
}

TEST(MeshDistance, StatisticsAgainstATiltedPlane) {
  // From (x, y, 0) on the unit square, the plane z = x is |x| / sqrt(2)
  // away, with x uniform in [0, 1]: max 1/sqrt(2) at the x = 1 corners,
  // mean and median 1/(2 sqrt(2)), rms 1/sqrt(6).
  const std::size_t n = 100000;
  const MeshDistanceStatistics s = meshDistance(square(0, 1, 0, 1, 0.0), square(-2, 3, -2, 3, 0.0, 1.0), {n, 3});
  const double r2 = std::sqrt(2.0);
  EXPECT_NEAR(s.max, 1.0 / r2, 1e-15);
  // Five standard errors of each statistic of n uniform draws, over sqrt(2).
  EXPECT_NEAR(s.mean, 0.5 / r2, 5 * std::sqrt(1.0 / 12 / n) / r2);
  EXPECT_NEAR(s.median, 0.5 / r2, 5 * 0.5 / std::sqrt(double(n)) / r2);
  EXPECT_NEAR(s.rms * s.rms, 1.0 / 6, 5 * std::sqrt(1.0 / 5 - 1.0 / 9) / std::sqrt(double(n)) / 2);
}

TEST(MeshDistance, MeshAgainstItselfIsZero) {
  const TriangleMesh sphere = makeIcosphere(3, 0.3, {1, -2, 0.5});
  const MeshDistanceStatistics s = meshDistance(sphere, sphere, {20000, 1});
  EXPECT_EQ(s.points, sphere.vertexCount() + 20000);
  EXPECT_LE(s.max, 1e-15);
  EXPECT_LE(s.rms, 1e-15);
  EXPECT_LE(hausdorffDistance(unitCube(), unitCube()), 1e-15);  // shifted-coordinate rounding only
}

TEST(MeshDistance, TranslatedCubeIsTheTranslationAway) {
  // Corner 0 of the cube lies outside the translated cube, whose nearest
  // point is its own corner 0: |t| away. No point is farther, as every
  // point has its translate on the other surface. The same holds backwards
  // from corner (1,1,1) + t.
  const Eigen::Vector3d t(0.1, 0.05, 0.02);
  const TriangleMesh a = unitCube(), b = unitCube(t);
  const MeshDistanceParameters params{20000, 7};
  const MeshDistanceStatistics ab = meshDistance(a, b, params), ba = meshDistance(b, a, params);
  EXPECT_NEAR(ab.max, t.norm(), 1e-15);
  EXPECT_NEAR(ba.max, t.norm(), 1e-15);
  EXPECT_LT(ab.mean, ab.max);
  EXPECT_NEAR(hausdorffDistance(a, b, params), t.norm(), 1e-15);
}

TEST(MeshDistance, ConcentricIcospheres) {
  // Icospheres of radii 1 and R = 1.1 around the origin, the outer one the
  // inner one scaled. Let c be the smallest distance from the centre to a
  // face plane of the inner one (its inradius); both are convex.
  //  - A point x of the inner surface is inside the outer one, whose
  //    surface crosses the ray through x at R|x|: so x is at most
  //    (R-1)|x| <= 0.1 from it. And the outer one contains the ball of
  //    radius R c, so x is at least R c - |x| >= R c - 1 from its surface.
  //  - A point y of the outer surface is y = R x for x on the inner
  //    surface, (R-1)|x| <= 0.1 away; and at least |y| - 1 >= R c - 1 from
  //    the inner one, which lies inside the unit ball.
  // Every distance, both ways, lies in [R c - 1, 0.1].
  const double R = 1.1;
  const TriangleMesh inner = makeIcosphere(4, 1.0), outer = makeIcosphere(4, R);
  double c = std::numeric_limits<double>::infinity();
  for (const Triangle& f : inner.faces) {
    const auto& p = inner.vertices.positions;
    const Eigen::Vector3d n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized();
    c = std::min(c, n.dot(p[f[0]]));
  }
  const double low = R * c - 1.0, high = 0.1;
  ASSERT_LT(high - low, 2e-3);  // the discretisation tolerance at 4 subdivisions (5120 faces)
  const double rounding = 1e-12;
  const MeshDistanceParameters params{50000, 1};
  for (const MeshDistanceStatistics& s : {meshDistance(inner, outer, params), meshDistance(outer, inner, params)}) {
    for (const double value : {s.max, s.mean, s.rms, s.median}) {
      EXPECT_GE(value, low - rounding);
      EXPECT_LE(value, high + rounding);
    }
    EXPECT_LE(s.median, s.max);
    EXPECT_LE(s.mean, s.rms);
  }
  const double h = hausdorffDistance(inner, outer, params);
  EXPECT_GE(h, low - rounding);
  EXPECT_LE(h, high + rounding);
}

TEST(MeshDistance, DeterministicWhateverTheThreads) {
  const TriangleMesh a = makeIcosphere(3, 1.0), b = makeIcosphere(2, 1.05, {0.01, 0, 0});
  const MeshDistanceParameters params{30000, 9};
  const MeshDistanceStatistics parallel = meshDistance(a, b, params);
  MeshDistanceStatistics serial;
  tbb::task_arena(1).execute([&] { serial = meshDistance(a, b, params); });
  EXPECT_EQ(parallel.max, serial.max);
  EXPECT_EQ(parallel.mean, serial.mean);
  EXPECT_EQ(parallel.rms, serial.rms);
  EXPECT_EQ(parallel.median, serial.median);
  EXPECT_NE(meshDistance(a, b, {30000, 10}).mean, parallel.mean);  // the seed matters
}

TEST(MeshDistance, VerticesOnlyAndErrors) {
  // A mesh without faces is measured at its vertices: a point cloud.
  TriangleMesh cloud;
  cloud.vertices.positions = {{0.5, 0.5, 2.0}, {0.5, 0.5, 0.5}, {2.0, 0.5, 0.5}};
  const MeshDistanceStatistics s = meshDistance(cloud, unitCube());
  EXPECT_EQ(s.points, 3u);
  EXPECT_DOUBLE_EQ(s.max, 1.0);
  EXPECT_DOUBLE_EQ(s.median, 1.0);
  EXPECT_DOUBLE_EQ(s.mean, 2.5 / 3);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt((1.0 + 0.25 + 1.0) / 3));

  EXPECT_THROW(meshDistance(unitCube(), cloud), std::invalid_argument);        // nothing to measure against
  EXPECT_THROW(meshDistance(TriangleMesh{}, unitCube()), std::invalid_argument);  // nothing to measure
  TriangleMesh broken = unitCube();
  broken.faces.emplace_back(0, 1, 42);
  EXPECT_THROW(meshDistance(broken, unitCube()), std::invalid_argument);
  EXPECT_THROW(hausdorffDistance(unitCube(), broken), std::invalid_argument);
}

}  // namespace
}  // namespace icrkit
