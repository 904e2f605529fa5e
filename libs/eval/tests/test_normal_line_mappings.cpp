// The normal-line mappings (eqs. 2, 3): identities, agreement with the
// exhaustive search, the far side and holes.

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/brute_force_mappings.hpp>
#include <icrkit/eval/normal_line_mappings.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

namespace icrkit::eval {
namespace {

// A sphere whose vertices are pushed along their normals by seeded noise:
// a stand-in for a reconstruction, with its own (different) triangulation.
TriangleMesh noisySphere(int subdivisions, double radius, double noise, unsigned seed) {
  TriangleMesh mesh = makeIcosphere(subdivisions, radius);
  std::mt19937 random(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3d n = turn * mesh.vertices.normals[v];
    mesh.vertices.positions[v] = (radius + gauss(random)) * n;
    mesh.vertices.normals[v] = n;
  }
  return mesh;
}

TEST(NormalLineMappings, IdenticalMeshesMapEveryVertexToItself) {
  const TriangleMesh mesh = makeIcosphere(3, 0.05);
  const CadToScanMapping c2s(mesh);
  const ScanToCadMapping s2c(mesh);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const VertexImage a = c2s.map(mesh.vertices.positions[v], mesh.vertices.normals[v]);
    const VertexImage b = s2c.map(mesh.vertices.positions[v], mesh.vertices.normals[v]);
    ASSERT_EQ(a.vertex, static_cast<int>(v));
    ASSERT_EQ(b.vertex, static_cast<int>(v));
    EXPECT_FALSE(a.fallback);
    EXPECT_NEAR(a.line_distance_m, 0.0, 1e-12);
  }
}

TEST(NormalLineMappings, AgreeWithBruteForceOnRandomPoints) {
  const TriangleMesh cad = makeIcosphere(4, 0.05);          // 2562 vertices
  const TriangleMesh scan = noisySphere(5, 0.05, 4e-4, 7);  // 10242 vertices, 0.4 mm noise
  const CadToScanMapping c2s(scan);
  const ScanToCadMapping s2c(cad);
  std::mt19937 random(3);
  std::uniform_int_distribution<std::size_t> pick_cad(0, cad.vertexCount() - 1), pick_scan(0, scan.vertexCount() - 1);
  std::normal_distribution<double> gauss(0.0, 1e-3);
  for (int trial = 0; trial < 300; ++trial) {
    // Off-vertex query points too: a CAD vertex moved off the surface, its normal tilted.
    const std::size_t v = pick_cad(random);
    const Eigen::Vector3d p = cad.vertices.positions[v] + Eigen::Vector3d(gauss(random), gauss(random), gauss(random));
    const Eigen::Vector3d n = (cad.vertices.normals[v] + 0.2 * Eigen::Vector3d(gauss(random), gauss(random), gauss(random)) / 1e-3).normalized();
    const VertexImage fast = c2s.map(p, n);
    const VertexImage slow = bruteForceCadToScan(scan, p, n, c2s.target().neighbourhoodRadius(), c2s.target().maxLineDistance());
    ASSERT_GE(fast.vertex, 0);
    // Embree crosses in single precision: an equal line distance is the same answer.
    EXPECT_TRUE(fast.vertex == slow.vertex || std::abs(fast.line_distance_m - slow.line_distance_m) < 1e-9)
        << "trial " << trial << ": " << fast.vertex << " vs " << slow.vertex;

    const std::size_t s = pick_scan(random);
    const VertexImage back = s2c.map(scan.vertices.positions[s], scan.vertices.normals[s]);
    const VertexImage back_slow = bruteForceScanToCad(cad, scan.vertices.positions[s], scan.vertices.normals[s],
                                                      s2c.target().neighbourhoodRadius(), s2c.target().maxLineDistance());
    ASSERT_EQ(back.vertex, back_slow.vertex) << "trial " << trial;
  }
}

// Two parallel squares 2 mm apart facing away from each other: a thin wall.
TriangleMesh thinWall(double gap, int n, double size) {
  TriangleMesh mesh;
  for (int side = 0; side < 2; ++side) {
    const double z = side == 0 ? gap / 2 : -gap / 2;
    const int base = static_cast<int>(mesh.vertexCount());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        mesh.vertices.positions.emplace_back(size * i / n - size / 2, size * j / n - size / 2, z);
        mesh.vertices.normals.emplace_back(0, 0, side == 0 ? 1.0 : -1.0);
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int a = base + i * (n + 1) + j, b = a + n + 1, c = b + 1, d = a + 1;
        if (side == 0) {
          mesh.faces.emplace_back(a, b, c);
          mesh.faces.emplace_back(a, c, d);
        } else {
          mesh.faces.emplace_back(a, c, b);
          mesh.faces.emplace_back(a, d, c);
        }
      }
  }
  return mesh;
}

TEST(NormalLineMappings, AThinWallsOtherSideIsNeverChosen) {
  const TriangleMesh wall = thinWall(0.002, 20, 0.04);
  TriangleMesh scan = wall;
  // The scan sits 1.8 mm high: from the CAD top side the nearest crossing is
  // the scan's bottom side (0.2 mm below), which faces the other way.
  for (auto& p : scan.vertices.positions) p.z() += 0.0018;
  const CadToScanMapping c2s(scan);
  const ScanToCadMapping s2c(wall);
  const std::size_t top_vertex = 5 * 21 + 7, bottom_vertex = 21 * 21 + top_vertex;
  const VertexImage image = c2s.map(wall.vertices.positions[top_vertex], wall.vertices.normals[top_vertex]);
  EXPECT_EQ(image.vertex, static_cast<int>(top_vertex));
  EXPECT_FALSE(image.fallback);
  // The scan's bottom vertex is nearest to the CAD top surface; its normal
  // says it belongs to the bottom side.
  const VertexImage back = s2c.map(scan.vertices.positions[bottom_vertex], scan.vertices.normals[bottom_vertex]);
  EXPECT_EQ(back.vertex, static_cast<int>(bottom_vertex));
}

TEST(NormalLineMappings, AScanPointInsideAThinWallMapsToTheSideItsNormalFaces) {
  // A cup's wall 2 mm thick seen with noise: the scan point lies 0.3 mm
  // above the wall's bottom sheet, nearer to it than to the top sheet, but
  // its normal says the finger comes from above. By touch, the finger meets
  // the top sheet; the nearest CAD point is on the bottom one, all of whose
  // vertices face away.
  const TriangleMesh wall = thinWall(0.002, 20, 0.04);
  const ScanToCadMapping s2c(wall);
  const std::size_t top_vertex = 8 * 21 + 9;
  const Eigen::Vector3d point = wall.vertices.positions[top_vertex] - Eigen::Vector3d(0, 0, 0.0017);
  const VertexImage image = s2c.map(point, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(image.vertex, static_cast<int>(top_vertex));
  EXPECT_FALSE(image.fallback);
  const VertexImage slow = bruteForceScanToCad(wall, point, Eigen::Vector3d::UnitZ(), s2c.target().neighbourhoodRadius(),
                                               s2c.target().maxLineDistance());
  EXPECT_EQ(slow.vertex, image.vertex);
  // Without a normal there is no side to touch: the nearest surface decides.
  const VertexImage unsided = s2c.map(point);
  EXPECT_EQ(unsided.vertex, static_cast<int>(21 * 21 + top_vertex));
}

TEST(NormalLineMappings, ALineThroughAHoleFallsBackToTheNearestSurface) {
  const TriangleMesh cad = thinWall(0.002, 20, 0.04);
  TriangleMesh scan = cad;
  // Remove the faces around the top vertex (10, 10).
  const int centre = 10 * 21 + 10;
  std::vector<Triangle> kept;
  for (const Triangle& f : scan.faces)
    if (f[0] != centre && f[1] != centre && f[2] != centre) kept.push_back(f);
  scan.faces = kept;
  const CadToScanMapping c2s(scan);
  const VertexImage image = c2s.map(cad.vertices.positions[centre], cad.vertices.normals[centre]);
  EXPECT_TRUE(image.fallback);
  // The centre vertex is left without faces, so it is no longer surface: a
  // neighbour one grid step (2 mm) away is the answer.
  EXPECT_NE(image.vertex, centre);
  EXPECT_NEAR(image.line_distance_m, 0.002, 1e-12);

  // Out of reach entirely: nothing.
  const VertexImage none = c2s.map(Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d::UnitZ());
  EXPECT_EQ(none.vertex, -1);
}

TEST(NormalLineMappings, BadParametersAndMeshesAreInputErrors) {
  const TriangleMesh mesh = makeIcosphere(1);
  MappingParameters bad;
  bad.max_line_distance = -1.0;
  EXPECT_THROW(CadToScanMapping(mesh, bad), InputError);
  bad = {};
  bad.neighbourhood_radius = std::nan("");
  EXPECT_THROW(ScanToCadMapping(mesh, bad), InputError);
  TriangleMesh no_faces = mesh;
  no_faces.faces.clear();
  EXPECT_THROW(CadToScanMapping{no_faces}, InputError);
  TriangleMesh no_normals = mesh;
  no_normals.vertices.normals.clear();
  EXPECT_THROW(ScanToCadMapping{no_normals}, InputError);
  const CadToScanMapping c2s(mesh);
  EXPECT_THROW(c2s.mapVertices(no_normals, {0}), InputError);
  EXPECT_THROW(c2s.mapVertices(mesh, {static_cast<int>(mesh.vertexCount())}), InputError);
}

}  // namespace
}  // namespace icrkit::eval
