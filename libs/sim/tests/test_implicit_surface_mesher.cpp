#include "implicit_surface_mesher.hpp"
#include "mesh_checks.hpp"
#include "sdf_primitives.hpp"

#include <icrkit/core/mesh_topology.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace icrkit::sim {
namespace {

using test::eulerCharacteristic;
using test::nonManifoldVertices;
using test::signedVolume;

constexpr double kPi = 3.14159265358979323846;

void expectClosedManifold(const TriangleMesh& mesh) {
  const EdgeStatistics s = edgeStatistics(mesh);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.misoriented_edges, 0u);
  EXPECT_EQ(nonManifoldVertices(mesh), 0u);
  EXPECT_GT(test::smallestFaceArea(mesh), 0.0);
  EXPECT_EQ(meshComponents(mesh).unreferenced_vertices, 0u);
}

// A sphere's mesh against the analytic area and volume. Every edge vertex
// lies on the sphere (root search), up to the 1 % clamp away from the nodes,
// and every face lies in one cube, so its edges are at most d = sqrt(3) h
// long. A point x = sum l_i v_i of a face with corners on the sphere has
// R^2 - |x|^2 = sum_{i<j} l_i l_j |v_i - v_j|^2 <= d^2 / 3, so the mesh lies
// in the shell R - h^2 / (2R) <= |x| <= R (+ 0.01 h for the clamp): the
// volume is short by at most 3 (h^2 / (2R) + 0.01 h) / R of the ball's and
// exceeds it by at most 3 (0.01 h) / R. The area converges at the same rate;
// it is also allowed the tilt of the faces, twice the volume bound.
TEST(ImplicitSurfaceMesher, SphereAreaAndVolumeWithinTheCellSizeBound) {
  const double radius = 0.05, cell = 0.002;
  // Several offsets of the sphere against the grid.
  const Eigen::Vector3d centres[] = {{0, 0, 0}, {0.00031, 0.00077, 0.00113}, {0.0009, 0.0001, 0.0015}};
  for (const Eigen::Vector3d& centre : centres) {
    const ScalarField field = [&](const Eigen::Vector3d& p) { return sdf::sphere(p, centre, radius); };
    const SampleGrid grid = gridAround(Eigen::AlignedBox3d(centre.array() - radius, centre.array() + radius), cell,
                                       Eigen::Vector3d::Zero());
    ImplicitMeshStatistics stats;
    TriangleMesh mesh = meshImplicitSurface(field, grid, &stats);
    // Measured about the sphere's centre: the volume formula holds anywhere,
    // the shift keeps its sums small.
    for (auto& p : mesh.vertices.positions) p -= centre;
    expectClosedManifold(mesh);
    EXPECT_EQ(eulerCharacteristic(mesh), 2);
    EXPECT_EQ(meshComponents(mesh).count, 1u);

    const double shrink = 3.0 * (cell * cell / (2.0 * radius) + 0.01 * cell) / radius;
    const double grow = 3.0 * 0.01 * cell / radius;
    const double volume = 4.0 / 3.0 * kPi * radius * radius * radius;
    const double area = 4.0 * kPi * radius * radius;
    const double v = signedVolume(mesh), a = surfaceArea(mesh);
    EXPECT_GE(v, volume * (1.0 - shrink));
    EXPECT_LE(v, volume * (1.0 + grow));
    EXPECT_NEAR(a, area, 2.0 * shrink * area);
    std::cout << "sphere R = " << radius << " m, cell " << cell << " m: volume error " << (v / volume - 1.0) * 100
              << " %, area error " << (a / area - 1.0) * 100 << " % (bound " << shrink * 100 << " %), "
              << mesh.vertexCount() << " vertices (" << stats.centre_vertices << " centre vertices)\n";

    // Every vertex on the level set, up to the clamp.
    double worst = 0.0;
    for (const auto& p : mesh.vertices.positions) worst = std::max(worst, std::abs(p.norm() - radius));
    EXPECT_LE(worst, 0.0101 * cell);
  }
}

TEST(ImplicitSurfaceMesher, TorusHasGenusOne) {
  const ScalarField field = [](const Eigen::Vector3d& p) {
    return std::hypot(std::hypot(p.x(), p.y()) - 0.03, p.z()) - 0.01;
  };
  const SampleGrid grid = gridAround(Eigen::AlignedBox3d(Eigen::Vector3d(-0.04, -0.04, -0.01),
                                                         Eigen::Vector3d(0.04, 0.04, 0.01)),
                                     0.0015, Eigen::Vector3d(0.0003, 0.0002, 0.0001));
  const TriangleMesh mesh = meshImplicitSurface(field, grid);
  expectClosedManifold(mesh);
  EXPECT_EQ(eulerCharacteristic(mesh), 0);
  EXPECT_EQ(meshComponents(mesh).count, 1u);
  const double volume = 2.0 * kPi * kPi * 0.03 * 0.01 * 0.01;
  EXPECT_NEAR(signedVolume(mesh), volume, 0.01 * volume);
}

// A gyroid sheet cut by a sphere, sampled coarsely: thin walls, saddles and
// every ambiguous face configuration. Whatever the topology the sampling
// gives, the surface must stay closed, manifold and oriented.
TEST(ImplicitSurfaceMesher, AmbiguousConfigurationsStayManifold) {
  const ScalarField field = [](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p * 300.0;
    const double gyroid = std::sin(q.x()) * std::cos(q.y()) + std::sin(q.y()) * std::cos(q.z()) +
                          std::sin(q.z()) * std::cos(q.x());
    return std::max(std::abs(gyroid) / 300.0 - 0.0008, p.norm() - 0.04);
  };
  std::size_t centre_vertices = 0;
  for (double cell : {0.0011, 0.0017, 0.0023}) {
    const SampleGrid grid = gridAround(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.04),
                                                           Eigen::Vector3d::Constant(0.04)),
                                       cell, Eigen::Vector3d::Zero());
    ImplicitMeshStatistics stats;
    const TriangleMesh mesh = meshImplicitSurface(field, grid, &stats);
    expectClosedManifold(mesh);
    EXPECT_GT(signedVolume(mesh), 0.0);
    EXPECT_GT(stats.loops, 0u);
    centre_vertices += stats.centre_vertices;
  }
  // Loops that no fan can cover (thin walls passing a cube twice) occur
  // here, and only here: the objects and simple shapes never need them.
  EXPECT_GT(centre_vertices, 0u);
}

// Two balls centred on diagonal nodes of one cube face, every other node
// outside: the face is ambiguous. The bilinear saddle value is negative
// (inside corners joined) when the radius exceeds half a cell. Far from
// that threshold the answer is also the true one: radius 0.8 cell, the
// balls overlap (one surface); 0.4 cell, they are apart (two).
TEST(ImplicitSurfaceMesher, AsymptoticDeciderOnAnAmbiguousFace) {
  const double cell = 0.001;
  const Eigen::Vector3d a(0, 0, 0), b(cell, cell, 0);
  for (double radius : {0.8 * cell, 0.4 * cell}) {
    const ScalarField field = [&](const Eigen::Vector3d& p) {
      return std::min(sdf::sphere(p, a, radius), sdf::sphere(p, b, radius));
    };
    const SampleGrid grid = gridAround(Eigen::AlignedBox3d(a, b), cell, a);
    const TriangleMesh mesh = meshImplicitSurface(field, grid);
    expectClosedManifold(mesh);
    const std::size_t surfaces = radius > 0.5 * cell ? 1 : 2;
    EXPECT_EQ(meshComponents(mesh).count, surfaces) << "radius " << radius;
    EXPECT_EQ(eulerCharacteristic(mesh), 2 * static_cast<long>(surfaces));
  }
}

TEST(ImplicitSurfaceMesher, Deterministic) {
  const ScalarField field = [](const Eigen::Vector3d& p) {
    return sdf::smoothUnite(sdf::sphere(p, {0.01, 0, 0}, 0.02), sdf::sphere(p, {-0.015, 0.005, 0}, 0.015), 0.005);
  };
  const SampleGrid grid = gridAround(Eigen::AlignedBox3d(Eigen::Vector3d(-0.035, -0.025, -0.025),
                                                         Eigen::Vector3d(0.035, 0.025, 0.025)),
                                     0.001, Eigen::Vector3d::Zero());
  const TriangleMesh a = meshImplicitSurface(field, grid), b = meshImplicitSurface(field, grid);
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  ASSERT_EQ(a.faceCount(), b.faceCount());
  for (std::size_t i = 0; i < a.vertexCount(); ++i)
    ASSERT_EQ(a.vertices.positions[i], b.vertices.positions[i]);
  for (std::size_t i = 0; i < a.faceCount(); ++i) ASSERT_EQ(a.faces[i], b.faces[i]);
}

TEST(ImplicitSurfaceMesher, RejectsASolidThatReachesTheGridBoundary) {
  const ScalarField field = [](const Eigen::Vector3d& p) { return sdf::sphere(p, {0, 0, 0}, 0.05); };
  const SampleGrid grid = gridAround(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.02),
                                                         Eigen::Vector3d::Constant(0.02)),
                                     0.002, Eigen::Vector3d::Zero());
  EXPECT_THROW(meshImplicitSurface(field, grid), std::invalid_argument);
  SampleGrid flat = grid;
  flat.nodes.z() = 1;
  EXPECT_THROW(meshImplicitSurface(field, flat), std::invalid_argument);
}

TEST(ImplicitSurfaceMesher, GridAroundHoldsTheBoundsAndTheAnchor) {
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-0.0113, 0.002, 0.5), Eigen::Vector3d(0.0207, 0.0031, 0.52));
  const Eigen::Vector3d anchor(0.0001, -0.0002, 0.00005);
  const SampleGrid grid = gridAround(bounds, 0.001, anchor, 2);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(grid.origin[a], bounds.min()[a] - 2 * grid.cell + 1e-12);
    EXPECT_GT(grid.origin[a], bounds.min()[a] - 3 * grid.cell);
    const double last = grid.origin[a] + (grid.nodes[a] - 1) * grid.cell;
    EXPECT_GE(last, bounds.max()[a] + 2 * grid.cell - 1e-12);
    EXPECT_LT(last, bounds.max()[a] + 3 * grid.cell);
    const double steps = (grid.origin[a] - anchor[a]) / grid.cell;
    EXPECT_NEAR(steps, std::round(steps), 1e-9);
  }
}

}  // namespace
}  // namespace icrkit::sim
