#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace icrkit;

TEST(MeshPrimitives, IcosphereIsAClosedOutwardSphere) {
  const Eigen::Vector3d centre(1, 2, 3);
  for (int s = 0; s <= 4; ++s) {
    const TriangleMesh m = makeIcosphere(s, 0.5, centre);
    const std::size_t four = std::size_t(1) << (2 * s);
    EXPECT_EQ(m.vertexCount(), 10 * four + 2);
    EXPECT_EQ(m.faceCount(), 20 * four);
    EXPECT_NO_THROW(m.validate());
    const EdgeStatistics e = edgeStatistics(m);
    EXPECT_EQ(e.boundary_edges, 0u);
    EXPECT_EQ(e.non_manifold_edges, 0u);
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
      EXPECT_NEAR((m.vertices.positions[v] - centre).norm(), 0.5, 1e-12);
      EXPECT_TRUE(m.vertices.normals[v].isApprox((m.vertices.positions[v] - centre) / 0.5, 1e-12));
    }
    double volume = 0;  // positive for outward winding
    for (const Triangle& f : m.faces) {
      const auto& p = m.vertices.positions;
      volume += (p[f[0]] - centre).dot((p[f[1]] - centre).cross(p[f[2]] - centre)) / 6.0;
    }
    EXPECT_GT(volume, 0.0);
  }
  // The area converges to 4 pi r^2 from below.
  const double area = surfaceArea(makeIcosphere(5, 1.0));
  EXPECT_LT(area, 4 * M_PI);
  EXPECT_GT(area, 0.999 * 4 * M_PI);
  EXPECT_THROW(makeIcosphere(-1), std::invalid_argument);
  EXPECT_THROW(makeIcosphere(2, 0.0), std::invalid_argument);
}
