#include "eval_test_meshes.hpp"

#include <icrkit/eval/geodesic_distances.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>

namespace icrkit::eval {
namespace {

using test::flatGrid;
using test::flatGridGraphDistance;

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(GeodesicDistances, FlatGridGeodesicsAreEdgeGraphPathLengths) {
  const int n = 21;
  const double h = 0.01;
  const TriangleMesh mesh = flatGrid(n, n, h);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  std::vector<int> all(mesh.vertexCount());
  std::iota(all.begin(), all.end(), 0);
  for (const auto& [si, sj] : {std::pair{10, 10}, std::pair{0, 0}, std::pair{20, 3}}) {
    const std::vector<double> d = graph.distances(sj * n + si, all, DistanceMetric::Geodesic, ws);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        ASSERT_NEAR(d[j * n + i], flatGridGraphDistance(i - si, j - sj, h), 1e-12)
            << "from (" << si << ", " << sj << ") to (" << i << ", " << j << ")";
  }
  // The field and the targeted query agree.
  const std::vector<double> field = graph.geodesicField(10 * n + 10, ws);
  const std::vector<double> d = graph.distances(10 * n + 10, all, DistanceMetric::Geodesic, ws);
  EXPECT_EQ(field, d);
}

TEST(GeodesicDistances, EuclideanOptionIsStraightLine) {
  const TriangleMesh mesh = makeIcosphere(2, 0.05);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  const std::vector<int> targets{0, 5, 17, 100, 161};
  const std::vector<double> e = graph.distances(3, targets, DistanceMetric::Euclidean, ws);
  const std::vector<double> g = graph.distances(3, targets, DistanceMetric::Geodesic, ws);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    EXPECT_DOUBLE_EQ(e[i], (mesh.vertices.positions[3] - mesh.vertices.positions[targets[i]]).norm());
    EXPECT_GE(g[i], e[i] - 1e-15);  // a surface path is never shorter than the straight line
  }
  EXPECT_DOUBLE_EQ(graph.eccentricity(3, targets, DistanceMetric::Euclidean, ws), *std::max_element(e.begin(), e.end()));
  const NearestVertex nearest = graph.nearest(3, targets, DistanceMetric::Euclidean, ws);
  const auto it = std::min_element(e.begin(), e.end());
  EXPECT_EQ(nearest.vertex, targets[static_cast<std::size_t>(it - e.begin())]);
  EXPECT_DOUBLE_EQ(nearest.distance, *it);
}

TEST(GeodesicDistances, NearestStopsAtTheFirstTargetAndBreaksTiesByIndex) {
  const int n = 101;
  const double h = 1.0 / 1024;  // exact in binary: equal edges have bitwise equal lengths
  const TriangleMesh mesh = flatGrid(n, n, h);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  const int centre = 50 * n + 50;
  // Equidistant along the axes (the same sum of equal edges): lower index wins.
  const std::vector<int> targets{50 * n + 53, 50 * n + 47, 90 * n + 90};
  const NearestVertex nearest = graph.nearest(centre, targets, DistanceMetric::Geodesic, ws);
  EXPECT_EQ(nearest.vertex, 50 * n + 47);
  EXPECT_NEAR(nearest.distance, 3 * h, 1e-15);
  // Early stop: only the ball of radius 3h was settled, not the mesh.
  EXPECT_LT(ws.settledVertices(), 60u);
  EXPECT_EQ(graph.nearest(centre, {centre, 0}, DistanceMetric::Geodesic, ws).distance, 0.0);
  EXPECT_EQ(graph.nearest(centre, {}, DistanceMetric::Geodesic, ws).vertex, -1);
}

TEST(GeodesicDistances, TargetedQueriesStopWhenAllTargetsAreSettled) {
  const int n = 101;
  const double h = 0.001;
  const TriangleMesh mesh = flatGrid(n, n, h);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  const int centre = 50 * n + 50;
  const std::vector<double> d =
      graph.distances(centre, {50 * n + 52, 52 * n + 52, 50 * n + 52}, DistanceMetric::Geodesic, ws);
  EXPECT_NEAR(d[0], 2 * h, 1e-15);
  EXPECT_NEAR(d[1], 2 * std::sqrt(2.0) * h, 1e-15);
  EXPECT_EQ(d[0], d[2]);
  EXPECT_LT(ws.settledVertices(), 100u);
}

TEST(GeodesicDistances, EccentricityGivesUpBeyondTheBound) {
  const int n = 41;
  const double h = 0.01;
  const TriangleMesh mesh = flatGrid(n, n, h);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  const int centre = 20 * n + 20;
  const std::vector<int> targets{20 * n + 30, 20 * n + 10, 0};  // 10h, 10h, 20 sqrt(2) h
  const double full = graph.eccentricity(centre, targets, DistanceMetric::Geodesic, ws);
  EXPECT_NEAR(full, 20 * std::sqrt(2.0) * h, 1e-12);
  EXPECT_EQ(graph.eccentricity(centre, targets, DistanceMetric::Geodesic, ws, full), full);  // equal: kept
  const std::uint64_t before = ws.settledVertices();
  EXPECT_EQ(graph.eccentricity(centre, targets, DistanceMetric::Geodesic, ws, 0.15), kInf);
  // The abandoned search stayed inside the radius 0.15 (a few hundred vertices, not 1681).
  EXPECT_LT(ws.settledVertices() - before, 800u);
  EXPECT_EQ(graph.eccentricity(centre, targets, DistanceMetric::Euclidean, ws, 0.15), kInf);
  EXPECT_EQ(graph.eccentricity(centre, {}, DistanceMetric::Geodesic, ws), 0.0);
}

TEST(GeodesicDistances, ComponentsBoundaryAndUnreachableTargets) {
  TriangleMesh mesh = flatGrid(5, 5, 0.1);
  const TriangleMesh other = flatGrid(3, 3, 0.1, Eigen::Vector3d(2.0, 0.0, 0.0));
  const int offset = static_cast<int>(mesh.vertexCount());
  for (const auto& p : other.vertices.positions) mesh.vertices.positions.push_back(p);
  for (const auto& f : other.faces) mesh.faces.push_back(f + Triangle::Constant(offset));
  mesh.vertices.positions.emplace_back(5.0, 5.0, 5.0);  // used by no face
  const int lonely = static_cast<int>(mesh.vertexCount()) - 1;

  const MeshDistanceGraph graph(mesh);
  EXPECT_EQ(graph.componentCount(), 3u);
  EXPECT_EQ(graph.component(0), 0);
  EXPECT_EQ(graph.component(offset), 1);
  EXPECT_EQ(graph.component(lonely), 2);
  EXPECT_TRUE(graph.onMeshBoundary(0));
  EXPECT_TRUE(graph.onMeshBoundary(2));    // middle of the bottom row
  EXPECT_FALSE(graph.onMeshBoundary(12));  // grid centre
  EXPECT_FALSE(graph.onMeshBoundary(offset + 4));  // centre of the small grid
  EXPECT_TRUE(graph.onMeshBoundary(lonely));

  DistanceWorkspace ws;
  const std::vector<double> d = graph.distances(0, {offset, 24, lonely}, DistanceMetric::Geodesic, ws);
  EXPECT_EQ(d[0], kInf);
  EXPECT_NEAR(d[1], 4 * std::sqrt(2.0) * 0.1, 1e-12);
  EXPECT_EQ(d[2], kInf);
  EXPECT_EQ(graph.eccentricity(0, {24, offset}, DistanceMetric::Geodesic, ws), kInf);
  EXPECT_EQ(graph.nearest(0, {offset, lonely}, DistanceMetric::Geodesic, ws).vertex, -1);
  EXPECT_TRUE(std::isfinite(graph.distances(0, {offset}, DistanceMetric::Euclidean, ws)[0]));
}

TEST(GeodesicDistances, WorkspaceIsReusableAcrossQueriesAndMeshes) {
  const TriangleMesh small = flatGrid(4, 4, 1.0);
  const TriangleMesh large = flatGrid(30, 30, 1.0);
  const MeshDistanceGraph a(small), b(large);
  DistanceWorkspace ws;
  for (int round = 0; round < 3; ++round) {
    EXPECT_NEAR(a.distances(0, {15}, DistanceMetric::Geodesic, ws)[0], 3 * std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(b.distances(29, {0}, DistanceMetric::Geodesic, ws)[0], 29.0, 1e-12);
    // Not-reached vertices from an earlier query must not leak into a later one.
    EXPECT_NEAR(b.distances(0, {1}, DistanceMetric::Geodesic, ws)[0], 1.0, 1e-12);
    EXPECT_NEAR(b.distances(0, {899}, DistanceMetric::Geodesic, ws)[0], 29 * std::sqrt(2.0), 1e-12);
  }
}

TEST(GeodesicDistances, BadInputThrowsInputError) {
  const TriangleMesh mesh = flatGrid(3, 3, 1.0);
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  EXPECT_THROW(graph.distances(9, {0}, DistanceMetric::Geodesic, ws), InputError);
  EXPECT_THROW(graph.distances(0, {-1}, DistanceMetric::Geodesic, ws), InputError);
  EXPECT_THROW(graph.nearest(0, {9}, DistanceMetric::Euclidean, ws), InputError);
  EXPECT_THROW(graph.eccentricity(0, {9}, DistanceMetric::Geodesic, ws), InputError);
  TriangleMesh broken = mesh;
  broken.faces.emplace_back(0, 1, 42);
  EXPECT_THROW(MeshDistanceGraph{broken}, InputError);
}

// How much the graph overestimates great-circle distances on a sphere, over
// all pairs (source, v) with `sources` spread sources and v at least
// `min_edges` mean edge lengths away.
struct Overestimate {
  double mean = 0.0, p95 = 0.0, max = 0.0, min = kInf;
};
Overestimate sphereOverestimate(const TriangleMesh& mesh, const MeshDistanceGraph& graph, int sources,
                                double min_edges) {
  double edge_sum = 0.0;
  std::size_t edges = 0;
  const VertexAdjacency& adjacency = graph.adjacency();
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    for (const int* w = adjacency.begin(v); w != adjacency.end(v); ++w, ++edges)
      edge_sum += (mesh.vertices.positions[v] - mesh.vertices.positions[static_cast<std::size_t>(*w)]).norm();
  const double min_distance = min_edges * edge_sum / static_cast<double>(edges);
  DistanceWorkspace ws;
  std::vector<double> ratios;
  for (int s = 0; s < sources; ++s) {
    const int source = static_cast<int>((mesh.vertexCount() - 1) * s / std::max(1, sources - 1));
    const std::vector<double> d = graph.geodesicField(source, ws);
    const Eigen::Vector3d a = mesh.vertices.positions[static_cast<std::size_t>(source)];
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
      const Eigen::Vector3d& b = mesh.vertices.positions[v];
      const double arc = a.norm() * std::atan2(a.cross(b).norm(), a.dot(b));
      if (arc >= min_distance) ratios.push_back(d[v] / arc - 1.0);
    }
  }
  std::sort(ratios.begin(), ratios.end());
  Overestimate o;
  o.min = ratios.front();
  o.max = ratios.back();
  o.p95 = ratios[ratios.size() * 95 / 100];
  o.mean = std::accumulate(ratios.begin(), ratios.end(), 0.0) / static_cast<double>(ratios.size());
  return o;
}

std::ostream& operator<<(std::ostream& out, const Overestimate& o) {
  return out << "mean " << 100 * o.mean << " %, p95 " << 100 * o.p95 << " %, max " << 100 * o.max << " %, min "
             << 100 * o.min << " %";
}

TEST(GeodesicDistances, SphereOverestimateIsBounded) {
  // The figures quoted in geodesic_distances.hpp come from here (pairs at least
  // 5 / 20 mean edge lengths apart, 7 sources).
  const TriangleMesh ico = makeIcosphere(5);
  const TriangleMesh uv = test::uvSphere(64, 128);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const MeshDistanceGraph ico_graph(ico, {paths}), uv_graph(uv, {paths});
    const char* name = paths == GeodesicPaths::Edges ? "edges" : "edges+unfolded diagonals";
    for (const double min_edges : {5.0, 20.0}) {
      const Overestimate i = sphereOverestimate(ico, ico_graph, 7, min_edges);
      const Overestimate u = sphereOverestimate(uv, uv_graph, 7, min_edges);
      std::cout << "[ overestimate ] " << name << ", >= " << min_edges << " edges: icosphere(5) " << i
                << "; UV sphere 64x128 " << u << "\n";
      // Chords are shorter than arcs, by ~(theta^2 / 24) ~ 1e-4 here: the only way below zero.
      EXPECT_GT(i.min, -1e-3);
      EXPECT_GT(u.min, -1e-3);
      if (paths == GeodesicPaths::Edges) {
        EXPECT_LT(i.mean, 0.08);
        EXPECT_LT(i.max, 0.25);
        EXPECT_LT(u.max, std::sqrt(2.0) - 1.0 + 0.01);  // quads split one way: Manhattan at worst
      } else {
        EXPECT_LT(i.mean, 0.02);
        EXPECT_LT(i.max, 0.06);
        EXPECT_LT(u.max, 0.13);
      }
    }
  }
}

TEST(GeodesicDistances, FlatGridOverestimateAgainstPlanarDistance) {
  // The worst case of a regular one-diagonal triangulation: exact along the
  // axes and the (1, 1) diagonal, Manhattan (x sqrt 2) along (1, -1).
  const int n = 41;
  const TriangleMesh mesh = flatGrid(n, n, 1.0);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const MeshDistanceGraph graph(mesh, {paths});
    DistanceWorkspace ws;
    const std::vector<double> d = graph.geodesicField(20 * n + 20, ws);
    double worst = 0.0, sum = 0.0;
    int count = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double planar = std::hypot(i - 20, j - 20);
        if (planar < 5.0) continue;
        const double ratio = d[j * n + i] / planar - 1.0;
        ASSERT_GT(ratio, -1e-12);
        worst = std::max(worst, ratio);
        sum += ratio;
        ++count;
      }
    std::cout << "[ overestimate ] flat grid, "
              << (paths == GeodesicPaths::Edges ? "edges" : "edges+unfolded diagonals") << ": mean "
              << 100 * sum / count << " % max " << 100 * worst << " %\n";
    if (paths == GeodesicPaths::Edges) {
      EXPECT_NEAR(worst, std::sqrt(2.0) - 1.0, 1e-9);
    } else {
      EXPECT_LT(worst, 0.1);
    }
  }
}

}  // namespace
}  // namespace icrkit::eval
