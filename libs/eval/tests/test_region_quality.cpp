#include "eval_test_meshes.hpp"

#include <icrkit/eval/region_quality.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>

#include <gtest/gtest.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numeric>
#include <random>

namespace icrkit::eval {
namespace {

using test::flatGrid;
using test::gridDisk;
using test::triangularLattice;
using test::verticesWithin;

// The definition, literally: every vertex's full eccentricity.
CentralPoint bruteForceCentralPoint(const MeshDistanceGraph& graph, std::vector<int> set, DistanceMetric metric) {
  std::sort(set.begin(), set.end());
  set.erase(std::unique(set.begin(), set.end()), set.end());
  DistanceWorkspace ws;
  CentralPoint best;
  best.eccentricity_m = std::numeric_limits<double>::infinity();
  for (int v : set) {
    const std::vector<double> d = graph.distances(v, set, metric, ws);
    const double e = *std::max_element(d.begin(), d.end());
    if (e < best.eccentricity_m) best.vertex = v, best.eccentricity_m = e;  // ascending: ties keep the lower
  }
  return best;
}

std::vector<int> ball(const MeshDistanceGraph& graph, int centre, double radius) {
  DistanceWorkspace ws;
  const std::vector<double> field = graph.geodesicField(centre, ws, radius);
  std::vector<int> out;
  for (std::size_t v = 0; v < field.size(); ++v)
    if (std::isfinite(field[v])) out.push_back(static_cast<int>(v));
  return out;
}

TEST(RegionQuality, BorderIsRegionVerticesWithAnOutsideNeighbourOrOnTheMeshBoundary) {
  const int n = 31;
  const TriangleMesh mesh = flatGrid(n, n, 0.01);
  const MeshDistanceGraph graph(mesh);
  const std::vector<int> disk = gridDisk(n, n, 15, 15, 5);
  const std::vector<int> border = regionBorder(graph, disk);
  EXPECT_TRUE(std::is_sorted(border.begin(), border.end()));
  for (int v : disk) {
    const int i = v % n - 15, j = v / n - 15;
    bool outside_neighbour = false;
    for (const int* w = graph.adjacency().begin(v); w != graph.adjacency().end(v); ++w)
      outside_neighbour |= !std::binary_search(disk.begin(), disk.end(), *w);
    EXPECT_EQ(std::binary_search(border.begin(), border.end(), v), outside_neighbour) << i << ", " << j;
  }
  EXPECT_FALSE(std::binary_search(border.begin(), border.end(), 15 * n + 15));
  EXPECT_TRUE(std::binary_search(border.begin(), border.end(), 15 * n + 20));
  EXPECT_EQ(regionBorder(graph, {7}), std::vector<int>{7});
  EXPECT_EQ(regionBorder(graph, {}), std::vector<int>{});
  // The whole mesh: its border is the mesh boundary.
  std::vector<int> all(mesh.vertexCount());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(regionBorder(graph, all).size(), static_cast<std::size_t>(4 * (n - 1)));
  // A half-disk cut by the mesh edge ends at that edge.
  const std::vector<int> half = gridDisk(n, n, 0, 15, 5);
  const std::vector<int> half_border = regionBorder(graph, half);
  for (int j = 10; j <= 20; ++j) EXPECT_TRUE(std::binary_search(half_border.begin(), half_border.end(), j * n));
}

TEST(RegionQuality, CentralPointOfADiskIsItsCentre) {
  const double h = 0.002;
  const int n = 61;
  const TriangleMesh lattice = triangularLattice(n, n, h);
  const int centre = 30 * n + 30;
  const std::vector<int> disk = verticesWithin(lattice, lattice.vertices.positions[centre], 12 * h);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const MeshDistanceGraph graph(lattice, {paths});
    DistanceWorkspace ws;
    for (const auto metric : {DistanceMetric::Euclidean, DistanceMetric::Geodesic}) {
      const CentralPoint c = centralPoint(graph, disk, metric, ws);
      EXPECT_EQ(c.vertex, centre);
      EXPECT_EQ(c.vertices, disk.size());
      EXPECT_LE(c.evaluations, 10u);  // the pruning at work: 1 of 583 in practice
    }
  }
  // On the one-diagonal grid the edge-graph metric is centrally symmetric,
  // so the centre is optimal, but it is constant along that diagonal over a
  // stretch: the lowest index of the tie, off centre, wins. An artefact of
  // the edge graph on such meshes, gone with the unfolded diagonals.
  const TriangleMesh grid = flatGrid(n, n, h);
  const std::vector<int> grid_disk = gridDisk(n, n, 30, 30, 12);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const MeshDistanceGraph graph(grid, {paths});
    DistanceWorkspace ws;
    EXPECT_EQ(centralPoint(graph, grid_disk, DistanceMetric::Euclidean, ws).vertex, centre);
    const CentralPoint g = centralPoint(graph, grid_disk, DistanceMetric::Geodesic, ws);
    EXPECT_EQ(g.eccentricity_m, graph.eccentricity(centre, grid_disk, DistanceMetric::Geodesic, ws));
    if (paths == GeodesicPaths::Edges) {
      EXPECT_EQ(g.vertex % n, g.vertex / n);  // on the diagonal through the centre
      EXPECT_LT(g.vertex, centre);
    } else {
      EXPECT_EQ(g.vertex, centre);
    }
  }
}

TEST(RegionQuality, PruningGivesTheBruteForceCentralPoint) {
  std::mt19937 rng(7);
  const TriangleMesh sphere = makeIcosphere(4, 0.1);
  const TriangleMesh grid = flatGrid(40, 40, 0.003);
  for (const TriangleMesh* mesh : {&sphere, &grid})
    for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
      const MeshDistanceGraph graph(*mesh, {paths});
      DistanceWorkspace ws;
      std::uniform_int_distribution<int> vertex(0, static_cast<int>(mesh->vertexCount()) - 1);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (int trial = 0; trial < 30; ++trial) {
        std::vector<int> set;
        if (trial % 3 == 2) {  // scattered vertices, far apart
          for (int i = 0; i < 25; ++i) set.push_back(vertex(rng));
        } else {  // a geodesic ball with holes bitten out
          const double radius = (mesh == &sphere ? 0.06 : 0.04) * (0.2 + unit(rng));
          for (int v : ball(graph, vertex(rng), radius))
            if (trial % 3 == 0 || unit(rng) < 0.6) set.push_back(v);
        }
        for (const auto metric : {DistanceMetric::Geodesic, DistanceMetric::Euclidean}) {
          const CentralPoint fast = centralPoint(graph, set, metric, ws);
          const CentralPoint slow = bruteForceCentralPoint(graph, set, metric);
          ASSERT_EQ(fast.vertex, slow.vertex) << "trial " << trial << ", " << set.size() << " vertices";
          ASSERT_EQ(fast.eccentricity_m, slow.eccentricity_m);
          EXPECT_LE(fast.evaluations, set.size());
        }
      }
    }
}

TEST(RegionQuality, IdenticalRegionsGiveOne) {
  const TriangleMesh mesh = makeIcosphere(4, 0.05);
  const RegionQualityEvaluator evaluator(mesh);
  DistanceWorkspace ws;
  const std::vector<int> region = ball(evaluator.graph(), 100, 0.015);
  std::vector<int> shuffled_with_duplicates = region;
  std::reverse(shuffled_with_duplicates.begin(), shuffled_with_duplicates.end());
  shuffled_with_duplicates.insert(shuffled_with_duplicates.end(), region.begin(), region.begin() + 10);
  const RegionQuality q = evaluator.evaluate(region, shuffled_with_duplicates, ws);
  ASSERT_TRUE(q.quality.has_value()) << q.reason;
  EXPECT_EQ(*q.quality, 1.0);
  EXPECT_EQ(q.cad_center, q.mapped_center);
  EXPECT_TRUE(q.mapped_center_inside);
  EXPECT_GT(q.d1_m, 0.01);
  EXPECT_EQ(q.d1_m, q.d2_m);
  EXPECT_EQ(q.mapped_vertices, region.size());
  EXPECT_EQ(q.reason, "");
}

TEST(RegionQuality, DisjointMappedRegionIsNegative) {
  const int n = 61;
  const double h = 0.001;
  const TriangleMesh mesh = flatGrid(n, n, h);
  for (const auto metric : {DistanceMetric::Geodesic, DistanceMetric::Euclidean}) {
    const RegionQualityEvaluator evaluator(mesh, {metric});
    DistanceWorkspace ws;
    const std::vector<int> cad = gridDisk(n, n, 20, 30, 8);
    const std::vector<int> mapped = gridDisk(n, n, 45, 30, 5);
    const RegionQuality q = evaluator.evaluate(cad, mapped, ws);
    ASSERT_TRUE(q.quality.has_value()) << q.reason;
    EXPECT_LT(*q.quality, 0.0);
    EXPECT_FALSE(q.mapped_center_inside);
    EXPECT_EQ(q.mapped_center, 30 * n + 45);
    EXPECT_NEAR(q.d2_m, -(45 - 28) * h, 1e-12);  // to the border vertex (28, 30)
    EXPECT_NEAR(*q.quality, q.d2_m / q.d1_m, 1e-15);
  }
}

TEST(RegionQuality, ShiftedDiskGivesTheRelativeShift) {
  const int n = 81;
  const double h = 0.001;
  const double r = 25, shift = 6;
  const TriangleMesh mesh = triangularLattice(n, n, h);
  const Eigen::Vector3d centre = mesh.vertices.positions[40 * n + 40];
  const std::vector<int> cad = verticesWithin(mesh, centre, r * h);
  // Along a lattice edge each way, and at 60 degrees (lattice vectors, so
  // that the shifted disk is the same vertex pattern).
  const std::vector<Eigen::Vector3d> shifts{Eigen::Vector3d(shift * h, 0, 0), Eigen::Vector3d(-shift * h, 0, 0),
                                            mesh.vertices.positions[46 * n + 43] - centre};
  for (const auto metric : {DistanceMetric::Geodesic, DistanceMetric::Euclidean})
    for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals})
      for (const Eigen::Vector3d& offset : shifts) {
        ASSERT_NEAR(offset.norm(), shift * h, 1e-12);
        const RegionQualityEvaluator evaluator(mesh, {metric, paths});
        DistanceWorkspace ws;
        const std::vector<int> mapped = verticesWithin(mesh, centre + offset, r * h);
        const RegionQuality q = evaluator.evaluate(cad, mapped, ws);
        ASSERT_TRUE(q.quality.has_value()) << q.reason;
        EXPECT_TRUE(q.mapped_center_inside);
        EXPECT_EQ(q.cad_center, 40 * n + 40);
        EXPECT_NEAR((mesh.vertices.positions[q.mapped_center] - centre - offset).norm(), 0.0, 1e-12);
        // Within mesh resolution: the border is a staircase up to one edge
        // inside the circle.
        EXPECT_NEAR(*q.quality, (r - shift) / r, 0.05) << "shift " << offset.transpose();
        EXPECT_NEAR(q.d1_m, r * h, 1.0 * h);
        EXPECT_NEAR(q.d2_m, (r - shift) * h, 1.0 * h);
      }
}

TEST(RegionQuality, SingleVertexRegionIsDegenerate) {
  const TriangleMesh mesh = flatGrid(10, 10, 0.01);
  const RegionQualityEvaluator evaluator(mesh);
  DistanceWorkspace ws;
  const RegionQuality q = evaluator.evaluate({45}, {45, 46}, ws);
  EXPECT_FALSE(q.quality.has_value());
  EXPECT_EQ(q.d1_m, 0.0);
  EXPECT_EQ(q.cad_center, 45);
  EXPECT_EQ(q.reason, "d1 = 0: the CAD central point is on the border");
  EXPECT_EQ(q.cad_border_vertices, 1u);
  EXPECT_EQ(q.mapped_center, 45);  // tie between the two: lower index
  EXPECT_TRUE(q.mapped_center_inside);
  EXPECT_EQ(q.d2_m, 0.0);
}

TEST(RegionQuality, EmptyMappedRegionIsReportedNotThrown) {
  const TriangleMesh mesh = triangularLattice(20, 20, 0.01);
  const RegionQualityEvaluator evaluator(mesh);
  DistanceWorkspace ws;
  const RegionQuality q =
      evaluator.evaluate(verticesWithin(mesh, mesh.vertices.positions[10 * 20 + 10], 0.04), {}, ws);
  EXPECT_FALSE(q.quality.has_value());
  EXPECT_EQ(q.reason, "empty mapped region");
  EXPECT_EQ(q.mapped_center, -1);
  EXPECT_EQ(q.mapped_vertices, 0u);
  EXPECT_EQ(q.cad_center, 10 * 20 + 10);
  EXPECT_NEAR(q.d1_m, 0.04, 1e-12);
}

TEST(RegionQuality, RegionAtTheMeshEdgeIsBoundedByIt) {
  const int n = 41;
  const double h = 0.01;
  const TriangleMesh mesh = flatGrid(n, n, h);
  std::vector<int> all(mesh.vertexCount());
  std::iota(all.begin(), all.end(), 0);
  for (const auto metric : {DistanceMetric::Euclidean, DistanceMetric::Geodesic}) {
    const RegionQualityEvaluator evaluator(mesh, {metric, GeodesicPaths::EdgesAndUnfoldedDiagonals});
    DistanceWorkspace ws;
    // The whole mesh: no vertex has an outside neighbour, the mesh boundary
    // is the border, and the centre is half the side away from it.
    const CadRegionSummary whole = evaluator.summarize(all, ws);
    EXPECT_EQ(whole.border.size(), static_cast<std::size_t>(4 * (n - 1)));
    EXPECT_EQ(whole.center.vertex, 20 * n + 20);
    EXPECT_NEAR(whole.d1_m, 20 * h, 1e-12);
  }
  // A half-disk against the x = 0 edge: the minimax centre of a half-disk is
  // the centre of its circle, on the edge, hence on the border: degenerate.
  const RegionQualityEvaluator evaluator(mesh, {DistanceMetric::Euclidean});
  DistanceWorkspace ws;
  const std::vector<int> half = gridDisk(n, n, 0, 20, 8);
  const RegionQuality q = evaluator.evaluate(half, half, ws);
  EXPECT_EQ(q.cad_center, 20 * n);
  EXPECT_EQ(q.d1_m, 0.0);
  EXPECT_FALSE(q.quality.has_value());
}

TEST(RegionQuality, OtherComponentsAreIgnoredOrReported) {
  TriangleMesh mesh = flatGrid(21, 21, 0.01);
  const TriangleMesh other = flatGrid(5, 5, 0.01, Eigen::Vector3d(1.0, 0.0, 0.0));
  const int offset = static_cast<int>(mesh.vertexCount());
  for (const auto& p : other.vertices.positions) mesh.vertices.positions.push_back(p);
  for (const auto& f : other.faces) mesh.faces.push_back(f + Triangle::Constant(offset));
  const RegionQualityEvaluator evaluator(mesh);
  DistanceWorkspace ws;
  const std::vector<int> cad = gridDisk(21, 21, 10, 10, 6);
  // A few stray mapped vertices on the other component do not move the centre.
  std::vector<int> mapped = cad;
  mapped.push_back(offset + 12);
  mapped.push_back(offset + 13);
  const RegionQuality q = evaluator.evaluate(cad, mapped, ws);
  ASSERT_TRUE(q.quality.has_value()) << q.reason;
  EXPECT_EQ(*q.quality, 1.0);
  EXPECT_EQ(q.mapped_ignored, 2u);
  // All of them there: no geodesic distance to the CAD region.
  const RegionQuality away = evaluator.evaluate(cad, {offset + 12, offset + 13, offset + 7}, ws);
  EXPECT_FALSE(away.quality.has_value());
  EXPECT_EQ(away.reason, "mapped central point cannot reach the CAD region");
  EXPECT_FALSE(away.mapped_center_inside);
  // The Euclidean metric measures straight across.
  const RegionQualityEvaluator euclidean(mesh, {DistanceMetric::Euclidean});
  const RegionQuality straight = euclidean.evaluate(cad, {offset + 12, offset + 13, offset + 7}, ws);
  ASSERT_TRUE(straight.quality.has_value());
  EXPECT_LT(*straight.quality, 0.0);
}

TEST(RegionQuality, BadInputThrowsInputError) {
  const TriangleMesh mesh = flatGrid(10, 10, 0.01);
  const RegionQualityEvaluator evaluator(mesh);
  DistanceWorkspace ws;
  EXPECT_THROW(evaluator.evaluate(std::vector<int>{}, {1}, ws), InputError);
  EXPECT_THROW(evaluator.evaluate({1, 100}, {1}, ws), InputError);
  EXPECT_THROW(evaluator.evaluate({1, 2}, {-1}, ws), InputError);
  EXPECT_THROW(centralPoint(evaluator.graph(), {100}, DistanceMetric::Geodesic, ws), InputError);
  EXPECT_THROW(regionBorder(evaluator.graph(), {100}), InputError);
  try {
    evaluator.evaluate({1, 2, 300}, {1}, ws);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "CAD region");
    EXPECT_EQ(e.location(), "entry 2");
  }
}

// Many regions on one mesh, as the experiment runs them: random geodesic
// balls with random holes, their mapped counterparts shifted and thinned.
struct RegionPair {
  std::vector<int> cad, mapped;
};
std::vector<RegionPair> randomRegionPairs(const MeshDistanceGraph& graph, int count, double min_radius,
                                          double max_radius, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(graph.vertexCount()) - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RegionPair> pairs;
  for (int i = 0; i < count; ++i) {
    const int centre = vertex(rng);
    const double radius = min_radius + (max_radius - min_radius) * unit(rng);
    RegionPair p;
    p.cad = ball(graph, centre, radius);
    // Shift: start from a neighbour of a neighbour of the centre.
    int moved = centre;
    for (int step = 0; step < 1 + i % 5; ++step) {
      const auto& adj = graph.adjacency();
      moved = *(adj.begin(moved) + static_cast<std::ptrdiff_t>(rng() % adj.degree(moved)));
    }
    for (int v : ball(graph, moved, radius * (0.6 + 0.6 * unit(rng))))
      if (unit(rng) < 0.8) p.mapped.push_back(v);
    pairs.push_back(std::move(p));
  }
  return pairs;
}

void expectSame(const RegionQuality& a, const RegionQuality& b) {
  EXPECT_EQ(a.cad_center, b.cad_center);
  EXPECT_EQ(a.mapped_center, b.mapped_center);
  EXPECT_EQ(a.mapped_center_inside, b.mapped_center_inside);
  EXPECT_EQ(a.d1_m, b.d1_m);
  EXPECT_EQ(a.d2_m, b.d2_m);
  EXPECT_EQ(a.quality, b.quality);
  EXPECT_EQ(a.reason, b.reason);
}

TEST(RegionQuality, ThreadsGiveTheSerialAnswer) {
  const TriangleMesh mesh = makeIcosphere(4, 0.05);
  const RegionQualityEvaluator evaluator(mesh);
  const std::vector<RegionPair> pairs = randomRegionPairs(evaluator.graph(), 120, 0.004, 0.02, 3);
  std::vector<RegionQuality> serial(pairs.size()), parallel(pairs.size());
  DistanceWorkspace ws;
  for (std::size_t i = 0; i < pairs.size(); ++i) serial[i] = evaluator.evaluate(pairs[i].cad, pairs[i].mapped, ws);
  tbb::enumerable_thread_specific<DistanceWorkspace> workspaces;
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t i) {
    parallel[i] = evaluator.evaluate(pairs[i].cad, pairs[i].mapped, workspaces.local());
  });
  int with_quality = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    expectSame(serial[i], parallel[i]);
    with_quality += serial[i].quality.has_value();
  }
  EXPECT_GT(with_quality, 100);
}

TEST(RegionQuality, LargeRegionsOnALargeMeshAreCheap) {
  // The experiment's scale: a 40,962-vertex CAD mesh, regions of up to ~3000
  // vertices. Prints the cost; asserts only the pruning's effect (timing
  // asserts would be flaky under sanitizers).
  const TriangleMesh mesh = makeIcosphere(6, 0.1);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const auto built = std::chrono::steady_clock::now();
    const RegionQualityEvaluator evaluator(mesh, {DistanceMetric::Geodesic, paths});
    const double build_ms = millisecondsSince(built);
    const std::vector<RegionPair> pairs = randomRegionPairs(evaluator.graph(), 40, 0.04, 0.07, 11);
    DistanceWorkspace ws;
    std::size_t vertices = 0, evaluations = 0, centre_searches = 0;
    const auto start = std::chrono::steady_clock::now();
    for (const RegionPair& p : pairs) {
      const CadRegionSummary cad = evaluator.summarize(p.cad, ws);
      const RegionQuality q = evaluator.evaluate(cad, p.mapped, ws);
      EXPECT_TRUE(q.quality.has_value()) << q.reason;
      vertices += p.cad.size() + p.mapped.size();
      evaluations += cad.center.evaluations;
      ++centre_searches;
    }
    const double ms = millisecondsSince(start);
    std::cout << "[ cost ] " << (paths == GeodesicPaths::Edges ? "edges" : "unfolded") << ": graph " << build_ms
              << " ms; " << pairs.size() << " region pairs, mean " << vertices / (2 * pairs.size())
              << " vertices per region: " << ms / pairs.size() << " ms per pair, "
              << static_cast<double>(evaluations) / centre_searches << " Dijkstras per CAD central point\n";
    EXPECT_LT(evaluations, 100 * centre_searches);
  }
}

TEST(RegionQuality, BandsAroundATubeStayExactAndAffordable) {
  // The hard case for Euclidean pruning: a region wrapped around a thin
  // handle, where straight lines cut across; geodesic anchors take over.
  // Exactness against brute force on a small tube:
  const TriangleMesh small = test::tube(60, 40, 0.01, 0.001);
  for (const auto paths : {GeodesicPaths::Edges, GeodesicPaths::EdgesAndUnfoldedDiagonals}) {
    const MeshDistanceGraph graph(small, {paths});
    DistanceWorkspace ws;
    for (const int span : {30, 45, 60}) {  // half-way, three quarters, all around
      std::vector<int> band;
      for (int r = 15; r < 25; ++r)
        for (int a = 0; a < span; ++a) band.push_back(r * 60 + a);
      const CentralPoint fast = centralPoint(graph, band, DistanceMetric::Geodesic, ws);
      const CentralPoint slow = bruteForceCentralPoint(graph, band, DistanceMetric::Geodesic);
      EXPECT_EQ(fast.vertex, slow.vertex) << span;
      EXPECT_EQ(fast.eccentricity_m, slow.eccentricity_m) << span;
    }
  }
  // Cost at the experiment's scale (printed; a band all the way around, not
  // measured here, needs O(k) Dijkstras, ~1-4 s for 3000 vertices, because
  // every vertex of a ring is nearly as central as any other).
  const TriangleMesh mesh = test::tube(120, 200, 0.01, 0.0005);  // 24,000 vertices, 1 cm radius
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace ws;
  for (const int span : {60, 90}) {
    std::vector<int> band;
    for (int r = 90; r < 115; ++r)
      for (int a = 0; a < span; ++a) band.push_back(r * 120 + a);
    const auto start = std::chrono::steady_clock::now();
    const CentralPoint c = centralPoint(graph, band, DistanceMetric::Geodesic, ws);
    const double ms = millisecondsSince(start);
    std::cout << "[ cost ] tube band " << span << "/120 around, " << band.size() << " vertices: " << c.evaluations
              << " Dijkstras, " << ms << " ms\n";
    EXPECT_LT(c.evaluations, band.size() / 5);
  }
}

}  // namespace
}  // namespace icrkit::eval
