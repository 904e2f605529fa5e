#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace icrkit;

namespace {

TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {Triangle(0, 2, 1), Triangle(0, 1, 3), Triangle(1, 2, 3), Triangle(0, 3, 2)};  // outward
  return m;
}

// An axis-aligned unit cube of 12 triangles, outward winding.
TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

double signedVolume(const TriangleMesh& m) {
  double v = 0;
  const auto& p = m.vertices.positions;
  for (const Triangle& f : m.faces) v += p[f[0]].dot(p[f[1]].cross(p[f[2]])) / 6.0;
  return v;
}

}  // namespace

TEST(MeshTopology, AdjacencyOfTwoTriangles) {
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
  m.faces = {Triangle(0, 1, 2), Triangle(0, 2, 3)};
  const VertexAdjacency a = vertexAdjacency(m);
  ASSERT_EQ(a.offsets.size(), 6u);
  EXPECT_EQ(std::vector<int>(a.begin(0), a.end(0)), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(std::vector<int>(a.begin(1), a.end(1)), (std::vector<int>{0, 2}));
  EXPECT_EQ(std::vector<int>(a.begin(2), a.end(2)), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(a.degree(4), 0u);
}

TEST(MeshTopology, FacesOfEachVertex) {
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
  m.faces = {Triangle(0, 1, 2), Triangle(0, 2, 3)};
  const VertexFaces f = vertexFaces(m);
  ASSERT_EQ(f.offsets.size(), 6u);
  EXPECT_EQ(std::vector<int>(f.begin(0), f.end(0)), (std::vector<int>{0, 1}));
  EXPECT_EQ(std::vector<int>(f.begin(1), f.end(1)), (std::vector<int>{0}));
  EXPECT_EQ(std::vector<int>(f.begin(2), f.end(2)), (std::vector<int>{0, 1}));
  EXPECT_EQ(std::vector<int>(f.begin(3), f.end(3)), (std::vector<int>{1}));
  EXPECT_EQ(f.begin(4), f.end(4));
}

TEST(MeshTopology, AreasEdgesAndComponents) {
  TriangleMesh t = tetrahedron();
  const auto areas = faceAreas(t);
  EXPECT_DOUBLE_EQ(areas[0], 0.5);
  EXPECT_NEAR(areas[2], std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(surfaceArea(t), 1.5 + std::sqrt(3.0) / 2.0, 1e-15);
  EdgeStatistics e = edgeStatistics(t);
  EXPECT_EQ(e.edges, 6u);
  EXPECT_EQ(e.boundary_edges, 0u);
  EXPECT_EQ(e.non_manifold_edges, 0u);

  TriangleMesh c = cube();
  EXPECT_NEAR(surfaceArea(c), 6.0, 1e-14);
  EXPECT_EQ(edgeStatistics(c).edges, 18u);

  // Two disjoint triangles and a fan of three triangles on one edge.
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {9, 9, 9}, {10, 9, 9}, {9, 10, 9}, {3, 3, 3}};
  m.faces = {Triangle(0, 1, 2), Triangle(1, 0, 3), Triangle(0, 1, 4), Triangle(5, 6, 7)};
  e = edgeStatistics(m);
  EXPECT_EQ(e.non_manifold_edges, 1u);
  EXPECT_EQ(e.boundary_edges, 6u + 3u);
  const MeshComponents comps = meshComponents(m);
  EXPECT_EQ(comps.count, 2u);
  EXPECT_EQ(comps.face_component, (std::vector<int>{0, 0, 0, 1}));
  EXPECT_EQ(comps.unreferenced_vertices, 1u);
}

TEST(MeshNormals, RepairsWindingAndTurnsClosedMeshesOutward) {
  TriangleMesh c = cube();
  // Flip a few faces and then the whole mesh's orientation.
  std::swap(c.faces[3][1], c.faces[3][2]);
  std::swap(c.faces[7][1], c.faces[7][2]);
  for (Triangle& f : c.faces) std::swap(f[1], f[2]);
  const OrientationReport report = orientFaces(c);
  EXPECT_EQ(report.conflicting_edges, 0u);
  EXPECT_EQ(report.flipped_faces, 10u);
  EXPECT_NEAR(signedVolume(c), 1.0, 1e-12);
  EXPECT_EQ(edgeStatistics(c).boundary_edges, 0u);

  computeVertexNormals(c);
  for (std::size_t v = 0; v < 8; ++v) {
    const Eigen::Vector3d outward = (c.vertices.positions[v] - Eigen::Vector3d(0.5, 0.5, 0.5)).normalized();
    EXPECT_NEAR(c.vertices.normals[v].norm(), 1.0, 1e-12);
    EXPECT_GT(c.vertices.normals[v].dot(outward), 0.9) << v;
  }
}

TEST(MeshNormals, OpenPatchFacesAwayFromItsCentroid) {
  // A bowl (hemisphere patch, pole at z = -1) seen as a partial view: its
  // outward side is the convex one, away from the sphere centre... the
  // normals must point away from the patch's centroid, i.e. downwards at the pole.
  TriangleMesh m;
  const int rings = 6, segments = 12;
  m.vertices.positions.emplace_back(0, 0, -1);
  for (int r = 1; r <= rings; ++r) {
    const double theta = (M_PI / 2) * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      m.vertices.positions.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta));
    }
  }
  auto id = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) m.faces.emplace_back(0, id(1, s), id(1, s + 1));  // inward-facing winding
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.faces.emplace_back(id(r, s), id(r + 1, s), id(r + 1, s + 1));
      m.faces.emplace_back(id(r, s), id(r + 1, s + 1), id(r, s + 1));
    }
  computeVertexNormals(m);
  EXPECT_LT(m.vertices.normals[0].z(), -0.99);
}

TEST(MeshTopology, ReferencedVerticesAreThoseOfFaces) {
  TriangleMesh t = tetrahedron();
  t.vertices.positions.insert(t.vertices.positions.begin() + 2, Eigen::Vector3d(7, 7, 7));
  for (Triangle& f : t.faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] >= 2) ++f[k];
  t.vertices.positions.emplace_back(-1, -1, -1);
  EXPECT_EQ(referencedVertices(t), (std::vector<std::uint8_t>{1, 1, 0, 1, 1, 0}));
  const std::vector<Eigen::Vector3d> surface = referencedPositions(t);
  ASSERT_EQ(surface.size(), 4u);
  EXPECT_EQ(surface[2], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(meshComponents(t).unreferenced_vertices, 2u);
  t.faces.clear();
  EXPECT_EQ(referencedVertices(t), std::vector<std::uint8_t>(6, 0));
  EXPECT_TRUE(referencedPositions(t).empty());
}

TEST(MeshNormals, UnusedVerticesBorrowTheNearestNormalAndChangeNothingElse) {
  const TriangleMesh clean = [] {
    TriangleMesh c = cube();
    computeVertexNormals(c);
    return c;
  }();
  TriangleMesh t = cube();
  // Equidistant from corners 1, 3, 5 and 7 (the x = 1 face): the lowest wins.
  t.vertices.positions.emplace_back(3, 0.5, 0.5);
  // Nearest corner 6 = (0, 1, 1).
  t.vertices.positions.emplace_back(-0.2, 1.1, 1.3);
  computeVertexNormals(t);
  ASSERT_EQ(t.vertices.normals.size(), 10u);
  for (std::size_t v = 0; v < 8; ++v) EXPECT_EQ(t.vertices.normals[v], clean.vertices.normals[v]) << v;
  EXPECT_EQ(t.vertices.normals[8], clean.vertices.normals[1]);
  EXPECT_EQ(t.vertices.normals[9], clean.vertices.normals[6]);
  for (const Eigen::Vector3d& n : t.vertices.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-12);

  // Only degenerate faces: nothing to borrow from, zero as documented.
  TriangleMesh flat;
  flat.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
  flat.faces = {Triangle(0, 1, 2)};
  computeVertexNormals(flat);
  for (const Eigen::Vector3d& n : flat.vertices.normals) EXPECT_EQ(n, Eigen::Vector3d::Zero());
}

namespace icrkit {
namespace {

// A 3 x 3 grid of unit squares (16 vertices, 18 faces) with the middle
// square removed: an outer boundary of 12 edges and a hole of 4.
TriangleMesh gridWithHole() {
  TriangleMesh m;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) m.vertices.positions.emplace_back(x, y, 0);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      if (x == 1 && y == 1) continue;
      const int a = y * 4 + x, b = a + 1, c = a + 5, d = a + 4;
      m.faces.emplace_back(a, b, c);
      m.faces.emplace_back(a, c, d);
    }
  return m;
}

TEST(MeshTopology, BoundaryLoopsFollowTheWinding) {
  const TriangleMesh m = gridWithHole();
  auto loops = boundaryLoops(m);
  ASSERT_EQ(loops.size(), 2u);
  std::sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
  EXPECT_EQ(loops[0].size(), 4u);
  EXPECT_EQ(loops[1].size(), 12u);
  // The outer loop runs counter-clockwise like the faces (seen from +z);
  // the hole's loop runs clockwise.
  auto signedArea = [&](const std::vector<int>& loop) {
    double a = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const auto& p = m.vertices.positions[loop[k]];
      const auto& q = m.vertices.positions[loop[(k + 1) % loop.size()]];
      a += p.x() * q.y() - q.x() * p.y();
    }
    return 0.5 * a;
  };
  EXPECT_DOUBLE_EQ(signedArea(loops[1]), 9.0);
  EXPECT_DOUBLE_EQ(signedArea(loops[0]), -1.0);
  EXPECT_EQ(edgeStatistics(m).boundary_edges, 16u);
  EXPECT_EQ(edgeStatistics(m).misoriented_edges, 0u);
}

TEST(MeshTopology, MisorientedEdgesAndClosedMeshes) {
  TriangleMesh m = gridWithHole();
  std::swap(m.faces[0][1], m.faces[0][2]);  // one face wound the other way
  // Its diagonal and its edge to the next square now run the same way as
  // their other faces; its third edge is on the boundary.
  EXPECT_EQ(edgeStatistics(m).misoriented_edges, 2u);
  TriangleMesh tetra;
  tetra.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  EXPECT_TRUE(boundaryLoops(tetra).empty());
  EXPECT_EQ(edgeStatistics(tetra).misoriented_edges, 0u);
  EXPECT_TRUE(traceBoundaryLoops({}).empty());
}

}  // namespace
}  // namespace icrkit
