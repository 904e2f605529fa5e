#include "meshing/point_insertion.hpp"

#include <icrkit/core/mesh_topology.hpp>

#include <Eigen/Geometry>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>
#include <set>

using namespace icrkit;
using namespace icrkit::reconstruction;
using Eigen::Vector3d;

namespace {

struct Patch {
  std::vector<Vector3d> positions, normals;
  std::vector<Triangle> faces;

  std::size_t add(const Vector3d& p, const Vector3d& n = Vector3d::UnitZ()) {
    positions.push_back(p);
    normals.push_back(n);
    return positions.size() - 1;
  }
  TriangleMesh mesh() const {
    TriangleMesh m;
    m.vertices.positions = positions;
    m.vertices.normals = normals;
    m.faces = faces;
    return m;
  }
  // Inserts `candidates` and takes the split faces back.
  PointInsertionReport insert(const std::vector<std::size_t>& candidates, const PointInsertionParameters& params) {
    TriangleMesh m = mesh();
    const PointInsertionReport r = insertPointsIntoMesh(m, candidates, params);
    faces = m.faces;
    return r;
  }
};

double signedAreaZ(const Patch& patch, const Triangle& f) {
  const Vector3d& a = patch.positions[f[0]];
  return 0.5 * (patch.positions[f[1]] - a).cross(patch.positions[f[2]] - a).z();
}

double totalArea(const Patch& patch) {
  double area = 0.0;
  for (const Triangle& f : patch.faces) area += signedAreaZ(patch, f);
  return area;
}

// Every face wound counter-clockwise about +z with a real area, every edge
// on at most two faces, run both ways when on two.
void expectManifoldAndUpright(const Patch& patch) {
  for (const Triangle& f : patch.faces) EXPECT_GT(signedAreaZ(patch, f), 1e-12);
  const EdgeStatistics edges = edgeStatistics(patch.mesh());
  EXPECT_EQ(edges.non_manifold_edges, 0u);
  EXPECT_EQ(edges.misoriented_edges, 0u);
}

PointInsertionParameters parameters(double max_offset, double separation) {
  PointInsertionParameters p;
  p.max_offset = max_offset;
  p.min_separation = separation;
  return p;
}

}  // namespace

TEST(PointInsertion, PointsInsideOneFaceSplitItWithoutChangingItsArea) {
  Patch patch;
  patch.add({0, 0, 0});
  patch.add({1, 0, 0});
  patch.add({0, 1, 0});
  patch.faces.emplace_back(0, 1, 2);
  std::vector<std::size_t> candidates;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0), h(-0.01, 0.01);
  while (candidates.size() < 40) {
    const double x = u(rng), y = u(rng);
    if (x + y < 0.9 && x > 0.1 && y > 0.1) candidates.push_back(patch.add({x, y, h(rng)}));
  }
  const PointInsertionReport r = patch.insert(candidates, parameters(0.05, 0.01));
  // 40 random points at least 0.1 from the sides: some may crowd each other.
  EXPECT_GE(r.inserted, 35u);
  EXPECT_EQ(r.inserted + r.left_out, candidates.size());
  EXPECT_EQ(patch.faces.size(), 1 + 2 * r.inserted);  // V + 1 gives F + 2 inside a triangle
  EXPECT_NEAR(totalArea(patch), 0.5, 1e-12);
  expectManifoldAndUpright(patch);
  // The outline is still the three sides: three boundary edges in one loop.
  EXPECT_EQ(edgeStatistics(patch.mesh()).boundary_edges, 3u);
  EXPECT_EQ(boundaryLoops(patch.mesh()).size(), 1u);
}

TEST(PointInsertion, APointNearASharedEdgeSplitsBothFacesThere) {
  // Two faces of a unit square meeting on the diagonal 1-2.
  Patch patch;
  patch.add({0, 0, 0});
  patch.add({1, 0, 0});
  patch.add({0, 1, 0});
  patch.add({1, 1, 0});
  patch.faces.emplace_back(0, 1, 2);
  patch.faces.emplace_back(2, 1, 3);
  const std::size_t near_diagonal = patch.add({0.5 + 0.001, 0.5 + 0.001, 0.002});
  const PointInsertionReport r = patch.insert({near_diagonal}, parameters(0.01, 0.02));
  EXPECT_EQ(r.inserted, 1u);
  EXPECT_EQ(r.onto_edges, 1u);
  ASSERT_EQ(patch.faces.size(), 4u);
  std::size_t faces_on_point = 0;
  for (const Triangle& f : patch.faces) faces_on_point += (f.array() == static_cast<int>(near_diagonal)).any();
  EXPECT_EQ(faces_on_point, 4u);
  // No crack: the square's four sides are the only boundary.
  EXPECT_EQ(edgeStatistics(patch.mesh()).boundary_edges, 4u);
  expectManifoldAndUpright(patch);
  EXPECT_NEAR(totalArea(patch), 1.0, 1e-4);
}

TEST(PointInsertion, PointsOffThePlaneFacingAwayOrCrowdingAVertexStayOut) {
  Patch patch;
  patch.add({0, 0, 0});
  patch.add({1, 0, 0});
  patch.add({0, 1, 0});
  patch.faces.emplace_back(0, 1, 2);
  const std::size_t too_far = patch.add({0.3, 0.3, 0.2});
  const std::size_t facing_away = patch.add({0.3, 0.3, 0.0}, -Vector3d::UnitZ());
  const std::size_t at_corner = patch.add({0.005, 0.005, 0.0});
  const std::size_t outside = patch.add({0.8, 0.8, 0.0});
  const std::vector<Triangle> before = patch.faces;
  const PointInsertionReport r = patch.insert({too_far, facing_away, at_corner, outside}, parameters(0.05, 0.02));
  EXPECT_EQ(r.inserted, 0u);
  EXPECT_EQ(r.left_out, 4u);
  EXPECT_EQ(patch.faces, before);
}

TEST(PointInsertion, TheSplitFaceIsDelaunayInItsPlane) {
  // A regular grid of points inside a large face: the Delaunay
  // triangulation of a square grid has no obtuse angle over 90 degrees
  // plus rounding, where an insertion order alone leaves long slivers.
  Patch patch;
  patch.add({0, 0, 0});
  patch.add({1, 0, 0});
  patch.add({0, 1, 0});
  patch.faces.emplace_back(0, 1, 2);
  std::vector<std::size_t> candidates;
  for (int i = 1; i < 10; ++i)
    for (int j = 1; j < 10; ++j)
      if (i + j < 9) candidates.push_back(patch.add({0.1 * i + 0.005, 0.1 * j + 0.005, 0.0}));
  const PointInsertionReport r = patch.insert(candidates, parameters(0.01, 0.02));
  EXPECT_EQ(r.inserted, candidates.size());
  expectManifoldAndUpright(patch);
  // Empty circumcircles: no vertex strictly inside any face's circumcircle.
  std::set<int> vertices;
  for (const Triangle& f : patch.faces) vertices.insert({f[0], f[1], f[2]});
  for (const Triangle& f : patch.faces) {
    const Eigen::Vector2d a = patch.positions[f[0]].head<2>(), b = patch.positions[f[1]].head<2>(),
                          c = patch.positions[f[2]].head<2>();
    const Eigen::Vector2d ab = b - a, ac = c - a;
    const double d = 2.0 * (ab.x() * ac.y() - ab.y() * ac.x());
    const Eigen::Vector2d centre = a + Eigen::Vector2d(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                                                       ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm()) /
                                           d;
    const double radius = (a - centre).norm();
    for (int v : vertices) EXPECT_GE((patch.positions[v].head<2>() - centre).norm(), radius - 1e-9) << "vertex " << v;
  }
}

TEST(PointInsertion, DeterministicWhateverTheOrderOfWork) {
  Patch patch;
  const int n = 12;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) patch.add({0.1 * i, 0.1 * j, 0.0});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + n + 1;
      patch.faces.emplace_back(a, b, a + 1);
      patch.faces.emplace_back(a + 1, b, b + 1);
    }
  std::vector<std::size_t> candidates;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.2), h(-0.002, 0.002);
  for (int k = 0; k < 2000; ++k) candidates.push_back(patch.add({u(rng), u(rng), h(rng)}));
  Patch again = patch;
  const PointInsertionReport r1 = patch.insert(candidates, parameters(0.01, 0.01));
  PointInsertionReport r2;
  {
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    r2 = again.insert(candidates, parameters(0.01, 0.01));
  }
  EXPECT_EQ(patch.faces, again.faces);
  EXPECT_EQ(r1.inserted, r2.inserted);
  EXPECT_GT(r1.inserted, 1000u);
  EXPECT_GT(r1.onto_edges, 50u);
  expectManifoldAndUpright(patch);
  // Points put onto the outer sides stay where they are, up to 0.01 off them.
  EXPECT_NEAR(totalArea(patch), 1.44, 0.01);
  EXPECT_EQ(boundaryLoops(patch.mesh()).size(), 1u);
  const MeshComponents parts = meshComponents(patch.mesh());
  EXPECT_EQ(parts.count, 1u);
}

TEST(PointInsertion, PointsAboveARidgeNeverMakeAThirdFaceOnAnEdge) {
  // A roof: two faces meeting on the ridge 0-1 at a right angle, and noisy
  // points around the ridge, many a little above it: they fall just
  // outside both faces' planes, as a noise layer does at a convex edge, and
  // go onto the ridge where they really are. Many random layers.
  std::size_t onto_edges = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    Patch patch;
    patch.add({0, 0, 0});
    patch.add({1, 0, 0});
    patch.add({0.5, 0.5, -0.5});
    patch.add({0.5, -0.5, -0.5});
    patch.faces.emplace_back(0, 1, 2);  // facing +y and up
    patch.faces.emplace_back(0, 3, 1);  // facing -y and up
    std::vector<std::size_t> candidates;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> x(0.02, 0.98), y(-0.02, 0.02), z(-0.004, 0.012);
    for (int k = 0; k < 200; ++k) {
      const Vector3d p(x(rng), y(rng), z(rng) - std::abs(y(rng)));
      candidates.push_back(patch.add(p, Vector3d(0, 0.3 * (p.y() > 0 ? 1 : -1), 1).normalized()));
    }
    const PointInsertionReport r = patch.insert(candidates, parameters(0.02, 0.01));
    onto_edges += r.onto_edges;
    const EdgeStatistics edges = edgeStatistics(patch.mesh());
    EXPECT_EQ(edges.non_manifold_edges, 0u) << "seed " << seed;
    EXPECT_EQ(edges.misoriented_edges, 0u) << "seed " << seed;
    for (const Triangle& f : patch.faces) {
      const Vector3d& a = patch.positions[f[0]];
      const Vector3d n = (patch.positions[f[1]] - a).cross(patch.positions[f[2]] - a);
      EXPECT_GT(n.dot(patch.normals[f[0]] + patch.normals[f[1]] + patch.normals[f[2]]), 0.0) << "seed " << seed;
    }
    EXPECT_EQ(boundaryLoops(patch.mesh()).size(), 1u) << "seed " << seed;
  }
  EXPECT_GT(onto_edges, 200u);
}
