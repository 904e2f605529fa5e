#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/ray_caster.hpp>
#include <icrkit/core/triangle_distance.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace icrkit {
namespace {

using test::unitCube;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Reference {
  double distance = kInf;
  int face = -1;
};

// Every face, in index order: the lowest index wins a tie, as in RayCaster.
Reference bruteForce(const TriangleMesh& mesh, const Eigen::Vector3d& q, const FaceMask& mask = {}) {
  Reference best;
  const auto& p = mesh.vertices.positions;
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    if (!mask.empty() && mask[i] == 0) continue;
    const Triangle& f = mesh.faces[i];
    const double d = closestPointOnTriangle(q, p[f[0]], p[f[1]], p[f[2]]).distance;
    if (d < best.distance) best = {d, static_cast<int>(i)};
  }
  return best;
}

// RayCaster measures in coordinates shifted to the bounding-box centre, so
// its distances may differ from the reference in the last bits, and of
// faces tied within that rounding either may win: the reported face must be
// as close as the reference's.
void expectMatches(const TriangleMesh& mesh, const Eigen::Vector3d& q, const ClosestPoint& c, const Reference& reference,
                   double tolerance) {
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.distance, reference.distance, tolerance);
  const auto& p = mesh.vertices.positions;
  const Triangle& f = mesh.faces[static_cast<std::size_t>(c.face)];
  EXPECT_NEAR(closestPointOnTriangle(q, p[f[0]], p[f[1]], p[f[2]]).distance, reference.distance, tolerance)
      << "face " << c.face << " instead of " << reference.face;
}

// The answer must describe one point of its face: barycentrics, point and
// distance consistent with each other.
void expectConsistent(const TriangleMesh& mesh, const Eigen::Vector3d& q, const ClosestPoint& c, double tolerance) {
  ASSERT_TRUE(c.found);
  const auto& p = mesh.vertices.positions;
  const Triangle& f = mesh.faces[static_cast<std::size_t>(c.face)];
  EXPECT_GE(c.u, 0.0);
  EXPECT_GE(c.v, 0.0);
  EXPECT_LE(c.u + c.v, 1.0 + 1e-12);
  EXPECT_LE(((1 - c.u - c.v) * p[f[0]] + c.u * p[f[1]] + c.v * p[f[2]] - c.point).norm(), tolerance);
  EXPECT_NEAR((q - c.point).norm(), c.distance, tolerance);
  EXPECT_NEAR(c.face_normal.norm(), 1.0, 1e-12);
}

TEST(ClosestPoint, KnownAnswersOnCube) {
  const TriangleMesh cube = unitCube();
  const RayCaster caster(cube);

  // Above the +z side: straight down onto it.
  ClosestPoint c = caster.closestPoint({0.3, 0.6, 2.0});
  ASSERT_TRUE(c.found);
  EXPECT_DOUBLE_EQ(c.distance, 1.0);
  EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(0.3, 0.6, 1.0), 1e-15));
  EXPECT_TRUE(c.face == 10 || c.face == 11);
  EXPECT_TRUE(c.face_normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-15));
  expectConsistent(cube, {0.3, 0.6, 2.0}, c, 1e-15);

  // Beyond a corner: the corner itself; four faces share it at the same
  // distance, the lowest index wins.
  c = caster.closestPoint({2.0, 3.0, 4.0});
  ASSERT_TRUE(c.found);
  EXPECT_DOUBLE_EQ(c.distance, std::sqrt(1.0 + 4.0 + 9.0));
  EXPECT_EQ(c.point, Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(c.face, bruteForce(cube, {2.0, 3.0, 4.0}).face);

  // Beyond an edge: the edge point.
  c = caster.closestPoint({-1.0, 0.25, -1.0});
  EXPECT_DOUBLE_EQ(c.distance, std::sqrt(2.0));
  EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(0, 0.25, 0), 1e-15));

  // Inside: the nearest side, from within.
  c = caster.closestPoint({0.5, 0.9, 0.4});
  EXPECT_NEAR(c.distance, 0.1, 1e-15);
  EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(0.5, 1.0, 0.4), 1e-15));
  EXPECT_TRUE(c.face_normal.isApprox(Eigen::Vector3d(0, 1, 0), 1e-15));

  // On the surface: distance 0, the point itself.
  c = caster.closestPoint({1.0, 0.5, 0.5});
  EXPECT_EQ(c.distance, 0.0);
  EXPECT_EQ(c.point, Eigen::Vector3d(1.0, 0.5, 0.5));
}

TEST(ClosestPoint, MaxDistanceIsInclusive) {
  const RayCaster caster(unitCube());
  const Eigen::Vector3d q(0.5, 0.5, 3.0);  // 2 m above the +z side
  EXPECT_FALSE(caster.closestPoint(q, 1.9).found);
  EXPECT_FALSE(caster.closestPoint(q, 0.0).found);
  const ClosestPoint at = caster.closestPoint(q, 2.0);
  ASSERT_TRUE(at.found);
  EXPECT_EQ(at.distance, 2.0);
  EXPECT_TRUE(caster.closestPoint(q, 2.1).found);
  EXPECT_TRUE(caster.closestPoint({0.5, 0.5, 1.0}, 0.0).found);  // on the surface
  EXPECT_THROW(caster.closestPoint(q, -1.0), std::invalid_argument);
  EXPECT_THROW(caster.closestPoint(q, std::nan("")), std::invalid_argument);
  EXPECT_THROW(caster.closestPoints({q}, -1.0), std::invalid_argument);
}

TEST(ClosestPoint, MaskExcludesFaces) {
  const TriangleMesh cube = unitCube();
  const RayCaster caster(cube);
  const Eigen::Vector3d q(0.5, 0.5, 1.5);
  FaceMask mask(12, 1);
  mask[10] = mask[11] = 0;  // the +z side
  const ClosestPoint c = caster.closestPoint(q, kInf, mask);
  ASSERT_TRUE(c.found);
  // Next nearest: the top edges of the four vertical sides, sqrt(0.5^2 + 0.5^2) away.
  EXPECT_NEAR(c.distance, std::sqrt(0.5), 1e-15);
  EXPECT_NE(c.face, 10);
  EXPECT_NE(c.face, 11);
  EXPECT_EQ(c.face, bruteForce(cube, q, mask).face);
  // Within max_distance only the masked side would do.
  EXPECT_FALSE(caster.closestPoint(q, 0.6, mask).found);
  EXPECT_TRUE(caster.closestPoint(q, 0.6).found);

  EXPECT_FALSE(caster.closestPoint(q, kInf, FaceMask(12, 0)).found);
  EXPECT_THROW(caster.closestPoint(q, kInf, FaceMask(11, 1)), std::invalid_argument);
  EXPECT_THROW(caster.closestPoints({q}, kInf, FaceMask(13, 1)), std::invalid_argument);
}

TEST(ClosestPoint, EmptyMeshAndBadQueries) {
  const RayCaster empty{TriangleMesh{}};
  EXPECT_FALSE(empty.closestPoint({0, 0, 0}).found);
  EXPECT_EQ(empty.closestPoints(std::vector<Eigen::Vector3d>(3, Eigen::Vector3d::Zero())).size(), 3u);
  const RayCaster caster(unitCube());
  EXPECT_FALSE(caster.closestPoint({std::nan(""), 0, 0}).found);
  EXPECT_FALSE(caster.closestPoint({kInf, 0, 0}).found);
}

TEST(ClosestPoint, FarFromTheWorldOriginKeepsPrecision) {
  // Embree's float scene rounds 1e6 to 6 cm; the answer must not.
  const Eigen::Vector3d shift(1.0e6, 2.0e6, 300.0);
  const RayCaster caster(unitCube(shift));
  const ClosestPoint c = caster.closestPoint(shift + Eigen::Vector3d(0.3, 0.6, 1.0 + 1e-7));
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.distance, 1e-7, 1e-9);
  EXPECT_NEAR((c.point - (shift + Eigen::Vector3d(0.3, 0.6, 1.0))).norm(), 0.0, 1e-9);
}

// Queries all around an icosphere: near the surface on both sides (where
// the float pruning is tightest), at the centre, and far away.
std::vector<Eigen::Vector3d> sphereQueries(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d direction = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    double radius;
    switch (i % 4) {
      case 0: radius = 1.0 + 1e-4 * (unit(rng) - 0.5); break;  // hugging the surface
      case 1: radius = unit(rng); break;                       // inside
      case 2: radius = 1.0 + 3.0 * unit(rng); break;           // outside
      default: radius = 1e3 * (1.0 + unit(rng)); break;        // far away
    }
    queries.push_back(radius * direction);
  }
  queries.push_back(Eigen::Vector3d::Zero());  // equidistant from many faces
  return queries;
}

TEST(ClosestPoint, IcosphereAgreesWithBruteForce) {
  const TriangleMesh sphere = makeIcosphere(3);  // 1280 faces
  const RayCaster caster(sphere);
  const auto queries = sphereQueries(2000, 5);
  const auto batch = caster.closestPoints(queries);
  ASSERT_EQ(batch.size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Reference reference = bruteForce(sphere, queries[i]);
    const ClosestPoint& c = batch[i];
    SCOPED_TRACE("query " + std::to_string(i));
    expectMatches(sphere, queries[i], c, reference, 1e-14 * (1.0 + queries[i].norm()));
    expectConsistent(sphere, queries[i], c, 1e-12 * (1.0 + queries[i].norm()));
    // The single query gives the same answer as the batch.
    const ClosestPoint single = caster.closestPoint(queries[i]);
    EXPECT_EQ(single.face, c.face);
    EXPECT_EQ(single.distance, c.distance);
    EXPECT_EQ(single.point, c.point);
  }
}

TEST(ClosestPoint, MaskAndMaxDistanceAgreeWithBruteForce) {
  const TriangleMesh sphere = makeIcosphere(2, 0.5, {0.1, -0.2, 0.3});
  const RayCaster caster(sphere);
  std::mt19937_64 rng(3);
  FaceMask mask(sphere.faceCount());
  for (auto& m : mask) m = static_cast<std::uint8_t>(rng() % 3 != 0);  // about a third masked out
  const auto queries = sphereQueries(1000, 9);
  const double max_distance = 0.3;
  const auto batch = caster.closestPoints(queries, max_distance, mask);
  std::size_t found = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Reference reference = bruteForce(sphere, queries[i], mask);
    ASSERT_EQ(batch[i].found, reference.distance <= max_distance) << "query " << i;
    if (!batch[i].found) continue;
    ++found;
    SCOPED_TRACE("query " + std::to_string(i));
    expectMatches(sphere, queries[i], batch[i], reference, 1e-14 * (1.0 + queries[i].norm()));
    EXPECT_NE(mask[static_cast<std::size_t>(batch[i].face)], 0);
  }
  EXPECT_GT(found, 100u);
  EXPECT_LT(found, queries.size());
}

TEST(ClosestPoint, BatchIsTheSameOnOneThread) {
  const RayCaster caster(makeIcosphere(3));
  const auto queries = sphereQueries(3000, 17);
  const auto parallel = caster.closestPoints(queries);
  std::vector<ClosestPoint> serial;
  tbb::task_arena(1).execute([&] { serial = caster.closestPoints(queries); });
  ASSERT_EQ(serial.size(), parallel.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    EXPECT_EQ(serial[i].face, parallel[i].face);
    EXPECT_EQ(serial[i].point, parallel[i].point);
  }
}

TEST(ClosestPointBunny, AgreesWithBruteForce) {
  const std::string path = test::sharedData("stanford-bunny/bun_zipper.ply");
  ICRKIT_REQUIRE_SHARED_FILE(path);
  const TriangleMesh bunny = io::readTriangleMesh(path);
  const RayCaster caster(bunny);
  // Vertices nudged off the surface (the hardest case for float pruning:
  // many faces within rounding of the answer), and points around the box.
  std::mt19937_64 rng(23);
  std::normal_distribution<double> gauss;
  const Eigen::AlignedBox3d box = bunny.vertices.bounds();
  const double size = box.diagonal().norm();
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < 150; ++i) {
    const auto& v = bunny.vertices.positions[rng() % bunny.vertexCount()];
    queries.push_back(v + 1e-5 * size * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)));
    queries.push_back(box.center() + 0.7 * size * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)));
  }
  const auto batch = caster.closestPoints(queries);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    SCOPED_TRACE("query " + std::to_string(i));
    expectMatches(bunny, queries[i], batch[i], bruteForce(bunny, queries[i]), 1e-14 * size);
  }
}

}  // namespace
}  // namespace icrkit
