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
