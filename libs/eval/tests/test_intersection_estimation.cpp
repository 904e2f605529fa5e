// Algorithm 2 and the false-positive area on meshes with known answers.

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/eval/finger_intersections.hpp>
#include <icrkit/eval/intersection_estimation.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

namespace icrkit::eval {
namespace {

// Vertices of `mesh` whose direction from the origin is within `angle` of `axis`.
std::vector<int> cap(const TriangleMesh& mesh, const Eigen::Vector3d& axis, double angle) {
  std::vector<int> region;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    if (mesh.vertices.positions[v].normalized().dot(axis.normalized()) >= std::cos(angle))
      region.push_back(static_cast<int>(v));
  return region;
}

double regionArea(const TriangleMesh& mesh, const std::vector<int>& region) {
  std::vector<std::uint8_t> in(mesh.vertexCount(), 0);
  for (int v : region) in[static_cast<std::size_t>(v)] = 1;
  const auto mask = regionFaceMask(mesh, in);
  const auto areas = faceAreas(mesh);
  double area = 0;
  for (std::size_t f = 0; f < areas.size(); ++f)
    if (mask[f]) area += areas[f];
  return area;
}

TEST(IntersectionEstimation, IdenticalMeshesGiveTheWholeRegionAndNoFalsePositives) {
  const TriangleMesh mesh = makeIcosphere(4, 0.05);
  const std::vector<int> region = cap(mesh, Eigen::Vector3d(1, 1, 0), 0.4);
  const IntersectionEstimator estimator(mesh);
  const RegionIntersection r = estimator.estimate(region, mesh, region);
  EXPECT_NEAR(r.cad_region_area_m2, regionArea(mesh, region), 1e-15);
  EXPECT_NEAR(r.intersection_area_m2 / r.cad_region_area_m2, 1.0, 1e-12);
  EXPECT_EQ(r.false_positive_area_m2, 0.0);
  EXPECT_EQ(r.unmapped, 0u);
  for (std::size_t i = 0; i < region.size(); ++i) EXPECT_EQ(r.mapped_vertices[i], region[i]);
}

TEST(IntersectionEstimation, ACopyShiftedAlongItsNormalsStillCoversTheRegion) {
  const TriangleMesh cad = makeIcosphere(4, 0.05);
  // Denser, 2 mm further out along every normal: a region of the same cap.
  const TriangleMesh scan = makeIcosphere(5, 0.052);
  const std::vector<int> cad_region = cap(cad, Eigen::Vector3d::UnitZ(), 0.5);
  const std::vector<int> scan_region = cap(scan, Eigen::Vector3d::UnitZ(), 0.5);
  const RegionIntersection r = IntersectionEstimator(cad).estimate(cad_region, scan, scan_region);
  EXPECT_GT(r.intersection_area_m2 / r.cad_region_area_m2, 0.97);
  // Only the rim of the scan cap maps beyond the CAD cap's last whole triangles.
  EXPECT_LT(r.false_positive_area_m2 / r.cad_region_area_m2, 0.08);
  EXPECT_EQ(r.unmapped, 0u);
}

TEST(IntersectionEstimation, ADisjointRegionIntersectsNothingAndIsAllFalsePositive) {
  const TriangleMesh mesh = makeIcosphere(4, 0.05);
  const std::vector<int> cad_region = cap(mesh, Eigen::Vector3d::UnitZ(), 0.4);
  const std::vector<int> scan_region = cap(mesh, Eigen::Vector3d::UnitX(), 0.4);
  const RegionIntersection r = IntersectionEstimator(mesh).estimate(cad_region, mesh, scan_region);
  EXPECT_EQ(r.intersection_area_m2, 0.0);
  EXPECT_TRUE(r.intersection_faces.empty());
  EXPECT_NEAR(r.false_positive_area_m2, r.scan_region_area_m2, 1e-15);
  EXPECT_NEAR(r.scan_region_area_m2, regionArea(mesh, scan_region), 1e-15);
}

TEST(IntersectionEstimation, HalfOverlapCountsHalf) {
  // A scan region that is the CAD cap's upper half (z above the cap's middle
  // latitude): Int = its share of the CAD cap, FP = 0.
  const TriangleMesh mesh = makeIcosphere(5, 0.05);
  const std::vector<int> cad_region = cap(mesh, Eigen::Vector3d::UnitZ(), 0.6);
  std::vector<int> half;
  for (int v : cad_region)
    if (mesh.vertices.positions[static_cast<std::size_t>(v)].x() >= 0.0) half.push_back(v);
  const RegionIntersection r = IntersectionEstimator(mesh).estimate(cad_region, mesh, half);
  const double expected = regionArea(mesh, half) / r.cad_region_area_m2;
  // Faces straddling the cut are hit through their corners on the half's rim.
  EXPECT_GE(r.intersection_area_m2 / r.cad_region_area_m2, expected - 1e-12);
  EXPECT_LT(r.intersection_area_m2 / r.cad_region_area_m2, expected + 0.06);
  EXPECT_EQ(r.false_positive_area_m2, 0.0);
}

TEST(IntersectionEstimation, OutOfRangeVerticesAreInputErrors) {
  const TriangleMesh mesh = makeIcosphere(2, 0.05);
  const IntersectionEstimator estimator(mesh);
  EXPECT_THROW(estimator.estimate({0, -1}, mesh, {0}), InputError);
  EXPECT_THROW(estimator.estimate({0}, mesh, {static_cast<int>(mesh.vertexCount())}), InputError);
  // An empty scan region is not an error: nothing intersects.
  const RegionIntersection r = estimator.estimate({0, 1, 2}, mesh, {});
  EXPECT_EQ(r.intersection_area_m2, 0.0);
  EXPECT_EQ(r.false_positive_area_m2, 0.0);
}

TEST(FingerIntersections, PairedByFingerNumber) {
  const TriangleMesh mesh = makeIcosphere(4, 0.05);
  const std::vector<int> a = cap(mesh, Eigen::Vector3d(1, 0, 0), 0.4);
  const std::vector<int> b = cap(mesh, Eigen::Vector3d(-1, 0, 0), 0.4);
  const IntersectionEstimator estimator(mesh);
  // The reconstruction lists the same fingers in the other order.
  const std::vector<FingerIntersection> pairs = intersectByFinger(estimator, {3, 5}, {a, b}, mesh, {5, 3}, {b, a});
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].finger, 3);
  EXPECT_EQ(pairs[0].scan_region, 1u);
  EXPECT_EQ(pairs[1].scan_region, 0u);
  for (const FingerIntersection& p : pairs) {
    EXPECT_NEAR(p.intersection.intersection_area_m2 / p.intersection.cad_region_area_m2, 1.0, 1e-12);
    EXPECT_EQ(p.intersection.false_positive_area_m2, 0.0);
  }
  const InputError missing = test::expectInputError([&] {
    intersectByFinger(estimator, {3, 5}, {a, b}, mesh, {3}, {a});
  });
  EXPECT_EQ(missing.source(), "reconstructed regions");
  EXPECT_NE(missing.detail().find("finger 5"), std::string::npos);
  EXPECT_EQ(test::expectInputError([&] {
              intersectByFinger(estimator, {3}, {a}, mesh, {3, 4}, {a, b});
            }).source(),
            "CAD regions");
  EXPECT_EQ(test::expectInputError([&] {
              intersectByFinger(estimator, {3, 4}, {a}, mesh, {3}, {a});
            }).source(),
            "CAD regions");
}

}  // namespace
}  // namespace icrkit::eval
