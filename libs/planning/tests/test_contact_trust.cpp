#include "planning_meshes.hpp"
#include "test_support.hpp"

#include <icrkit/planning/contact_trust.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace icrkit;
using namespace icrkit::planning;

TEST(ContactTrust, RimOfAnOpenSurfaceIsNotTrusted) {
  const TriangleMesh grid = test::flatGrid(0.04, 40);  // 1 mm spacing
  ContactTrustParameters params;
  params.rim_distance_m = 0.0045;
  const ContactTrust trust = assessContactTrust(grid, {}, params);
  for (std::size_t v = 0; v < grid.vertexCount(); ++v) {
    const Eigen::Vector3d& p = grid.vertices.positions[v];
    const double to_rim = std::min({p.x(), p.y(), 0.04 - p.x(), 0.04 - p.y()});
    // Along grid edges the distance to the rim is exact for this grid.
    EXPECT_EQ(trust.untrusted[v] != 0, to_rim < 0.0045 - 1e-9) << "vertex " << v << " at " << p.transpose();
  }
  EXPECT_EQ(trust.report.near_rim + trust.report.trusted, grid.vertexCount());
  EXPECT_EQ(trust.report.trusted, 31u * 31u);  // x, y in 5..35 mm
}

TEST(ContactTrust, CubeEdgesAreNotTrustedAndFaceCentresAre) {
  const TriangleMesh cube = test::griddedCube(0.04, 20);  // 2 mm spacing
  ContactTrustParameters params;
  params.footprint_radius_m = 0.003;
  params.max_normal_spread_rad = 0.35;
  const ContactTrust trust = assessContactTrust(cube, {}, params);
  EXPECT_EQ(trust.report.near_rim, 0u);  // closed
  for (std::size_t v = 0; v < cube.vertexCount(); ++v) {
    const Eigen::Vector3d& p = cube.vertices.positions[v];
    // Distance to the nearest cube edge: the second smallest distance to a face plane.
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = std::min(p[k], 0.04 - p[k]);
    std::sort(d, d + 3);
    const double to_edge = d[1];
    // Within 1 mm of an edge the blended normals sit under any footprint;
    // beyond footprint + spacing every normal under it is the face's.
    if (to_edge < 0.001) EXPECT_NE(trust.untrusted[v], 0) << p.transpose();
    if (to_edge > 0.003 + 0.002 + 1e-9) EXPECT_EQ(trust.untrusted[v], 0) << p.transpose();
  }
}

TEST(ContactTrust, ExcludedAndUncertainVerticesAreNotTrusted) {
  TriangleMesh grid = test::flatGrid(0.04, 40);
  std::vector<std::uint8_t> excluded(grid.vertexCount(), 0);
  const std::size_t centre = 20 * 41 + 20;
  excluded[centre] = 1;
  Attribute& sigma = grid.vertices.attributes.add("normal_sigma", ScalarType::Float32, grid.vertexCount(), 0.01);
  sigma.values[centre + 1] = 0.5;
  const ContactTrust trust = assessContactTrust(grid, excluded, {});
  EXPECT_NE(trust.untrusted[centre], 0);
  EXPECT_NE(trust.untrusted[centre + 1], 0);
  EXPECT_EQ(trust.untrusted[centre + 2], 0);
  EXPECT_EQ(trust.report.excluded, 1u);
  EXPECT_EQ(trust.report.normal_sigma, 1u);
}

TEST(ContactTrust, RefusesBadParameters) {
  const TriangleMesh grid = test::flatGrid(0.01, 4);
  ContactTrustParameters params;
  params.rim_distance_m = -1.0;
  EXPECT_EQ(test::expectInputError([&] { assessContactTrust(grid, {}, params); }).source(),
            "ContactTrustParameters::rim_distance_m");
  EXPECT_EQ(test::expectInputError([&] { assessContactTrust(grid, std::vector<std::uint8_t>(3, 0), {}); }).source(),
            "exclusion mask");
}

TEST(ContactTrust, ThinlySupportedSurfaceUnderTheFootprintIsNotTrusted) {
  // A plate whose centre (a 3 x 3 vertex patch) is supported by a tenth of
  // the typical point count: a ghost of a misregistered view. Every vertex
  // whose 3 mm footprint reaches the patch is untrusted, the rest are.
  TriangleMesh grid = test::flatGrid(0.04, 40);  // 1 mm spacing
  Attribute& support = grid.vertices.attributes.add("cardinality", ScalarType::Float32, grid.vertexCount(), 300.0);
  const auto index = [](int i, int j) { return static_cast<std::size_t>(i * 41 + j); };
  for (int i = 19; i <= 21; ++i)
    for (int j = 19; j <= 21; ++j) support.values[index(i, j)] = 30.0;
  ContactTrustParameters params;
  params.rim_distance_m = 0.0;
  const ContactTrust trust = assessContactTrust(grid, {}, params);
  for (int i = 1; i < 40; ++i)
    for (int j = 1; j < 40; ++j) {
      // Distance from (i, j) to the nearest patch vertex, in grid steps (1 mm).
      const double di = std::max(0, std::max(19 - i, i - 21)), dj = std::max(0, std::max(19 - j, j - 21));
      const double to_patch = 0.001 * std::hypot(di, dj);
      if (to_patch <= 0.003 - 1e-9) EXPECT_NE(trust.untrusted[index(i, j)], 0) << i << "," << j;
      if (to_patch > 0.003 + 1e-9) EXPECT_EQ(trust.untrusted[index(i, j)], 0) << i << "," << j;
    }
  EXPECT_GT(trust.report.weak_support, 9u);
  // Off: the patch is trusted like the rest.
  params.min_relative_support.reset();
  EXPECT_EQ(assessContactTrust(grid, {}, params).untrusted[index(20, 20)], 0);
}

TEST(ContactTrust, AFewNoisyNormalsUnderTheFootprintAreTolerated) {
  // One vertex's normal is tilted by 60 deg (ball pivoting's small triangles
  // give a few such): it is untrusted itself, its neighbours are not, unless
  // every normal under the footprint must agree (max_spread_fraction 0).
  TriangleMesh grid = test::flatGrid(0.04, 40);
  const std::size_t noisy = 20 * 41 + 20, neighbour = 20 * 41 + 22;
  grid.vertices.normals[noisy] = Eigen::Vector3d(std::sin(1.05), 0.0, std::cos(1.05));
  ContactTrustParameters params;
  params.rim_distance_m = 0.0;
  ContactTrust trust = assessContactTrust(grid, {}, params);
  EXPECT_NE(trust.untrusted[noisy], 0);
  EXPECT_EQ(trust.untrusted[neighbour], 0);
  params.max_spread_fraction = 0.0;
  trust = assessContactTrust(grid, {}, params);
  EXPECT_NE(trust.untrusted[noisy], 0);
  EXPECT_NE(trust.untrusted[neighbour], 0);
  params.max_spread_fraction = 1.0;
  EXPECT_EQ(test::expectInputError([&] { assessContactTrust(grid, {}, params); }).source(),
            "ContactTrustParameters::max_spread_fraction");
}

TEST(ContactTrust, RoundedFeaturesWithLowFlatnessAreNotTrusted) {
  // `flatness` (the NDT window's planarity) at a third of the median: the
  // smoothing rounded a feature there. Only that vertex is untrusted.
  TriangleMesh grid = test::flatGrid(0.04, 40);
  Attribute& flatness = grid.vertices.attributes.add("flatness", ScalarType::Float32, grid.vertexCount(), 3.0);
  const std::size_t rounded = 20 * 41 + 20, next = rounded + 1;
  flatness.values[rounded] = 1.0;
  flatness.values[next] = 2.4;  // 0.8 of the median: kept
  ContactTrustParameters params;
  params.rim_distance_m = 0.0;
  ContactTrust trust = assessContactTrust(grid, {}, params);
  EXPECT_NE(trust.untrusted[rounded], 0);
  EXPECT_EQ(trust.untrusted[next], 0);
  EXPECT_EQ(trust.report.low_flatness, 1u);
  params.min_relative_flatness.reset();
  trust = assessContactTrust(grid, {}, params);
  EXPECT_EQ(trust.untrusted[rounded], 0);
}
