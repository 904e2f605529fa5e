#include <icrkit/ndt/normal_orientation.hpp>
#include <icrkit/ndt/smoothing.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace icrkit::ndt {
namespace {

// A torus about z (tube radius b around a circle of radius a) with its true
// outward normals; on the inner equator they point towards the centroid,
// which a rule "away from the centroid" alone would get wrong.
struct Torus {
  PointCloud cloud;
  std::vector<Eigen::Vector3d> truth;
};

Torus randomTorus(std::size_t count, double a, double b, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Torus t;
  while (t.cloud.size() < count) {
    const double u = angle(rng), v = angle(rng);
    // Area element (a + b cos v): keep the sampling uniform on the surface.
    if (unit(rng) * (a + b) > a + b * std::cos(v)) continue;
    const Eigen::Vector3d ring(std::cos(u), std::sin(u), 0.0);
    const Eigen::Vector3d normal = std::cos(v) * ring + std::sin(v) * Eigen::Vector3d::UnitZ();
    t.cloud.positions.push_back(a * ring + b * normal);
    t.truth.push_back(normal);
    // A randomly signed copy of the true normal: orientation must undo it.
    t.cloud.normals.push_back(unit(rng) < 0.5 ? -normal : normal);
  }
  return t;
}

std::size_t disagreeing(const Torus& t) {
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < t.cloud.size(); ++i) wrong += t.cloud.normals[i].dot(t.truth[i]) < 0 ? 1 : 0;
  return wrong;
}

TEST(NormalOrientation, TorusNormalsAllPointOutOfTheTubeIncludingTheInnerSide) {
  Torus t = randomTorus(20000, 0.08, 0.03, 5);
  orientNormals(t.cloud, std::nullopt);
  EXPECT_EQ(disagreeing(t), 0u);
}

TEST(NormalOrientation, FlippedCountIsTheNumberOfNormalsThatChanged) {
  Torus t = randomTorus(5000, 0.08, 0.03, 6);
  const std::vector<Eigen::Vector3d> before = t.cloud.normals;
  const std::size_t flipped = orientNormals(t.cloud, std::nullopt);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < before.size(); ++i) changed += before[i].dot(t.cloud.normals[i]) < 0 ? 1 : 0;
  EXPECT_EQ(flipped, changed);
  EXPECT_GT(flipped, 1000u);
}

TEST(NormalOrientation, NearestNeighbourGraphListsTheNearestOtherPoints) {
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 6; ++i) line.emplace_back(i * i * 0.1, 0, 0);  // gaps grow along the line
  const NeighbourGraph graph = nearestNeighbourGraph(line, 2);
  ASSERT_EQ(graph.slots, 2u);
  EXPECT_EQ(graph.neighbours[0 * 2 + 0], 1u);
  EXPECT_EQ(graph.neighbours[0 * 2 + 1], 2u);
  EXPECT_EQ(graph.neighbours[3 * 2 + 0], 2u);
  EXPECT_EQ(graph.neighbours[3 * 2 + 1], 4u);
  const NeighbourGraph tiny = nearestNeighbourGraph({Eigen::Vector3d::Zero()}, 8);
  EXPECT_EQ(tiny.slots, 0u);
}

// Prim's algorithm, one tree at a time, on the same float weights: the
// reference the Kruskal forest must equal when no two weights tie.
std::vector<Eigen::Vector3d> orientedByPrim(const PointCloud& cloud, const NeighbourGraph& graph) {
  const std::size_t n = cloud.size();
  std::vector<std::vector<std::pair<float, std::size_t>>> adjacent(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t s = 0; s < graph.slots; ++s) {
      const std::size_t j = graph.neighbours[i * graph.slots + s];
      if (j >= n || j == i) continue;
      const float w = static_cast<float>(1.0 - std::abs(cloud.normals[i].dot(cloud.normals[j])));
      adjacent[i].emplace_back(w, j);
      adjacent[j].emplace_back(w, i);
    }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& q : cloud.positions) centroid += q;
  centroid /= static_cast<double>(n);
  auto outwardness = [&](std::size_t i) {
    const Eigen::Vector3d r = cloud.positions[i] - centroid;
    return r.norm() > 0 ? std::abs(cloud.normals[i].dot(r)) / r.norm() : -1.0;
  };
  std::vector<Eigen::Vector3d> normals = cloud.normals;
  std::vector<int> component(n, -1);
  for (std::size_t start = 0; start < n; ++start) {  // components by flood fill
    if (component[start] >= 0) continue;
    std::vector<std::size_t> members{start};
    component[start] = static_cast<int>(start);
    for (std::size_t k = 0; k < members.size(); ++k)
      for (const auto& [w, j] : adjacent[members[k]])
        if (component[j] < 0) {
          component[j] = static_cast<int>(start);
          members.push_back(j);
        }
    std::size_t root = *std::min_element(members.begin(), members.end());
    for (std::size_t m : members)
      if (outwardness(m) > outwardness(root) || (outwardness(m) == outwardness(root) && m < root)) root = m;
    if (normals[root].dot(cloud.positions[root] - centroid) < 0) normals[root] = -normals[root];
    std::vector<std::uint8_t> in_tree(n, 0);
    in_tree[root] = 1;
    for (std::size_t added = 1; added < members.size(); ++added) {
      float best = 2.0f;
      std::size_t from = n, to = n;
      for (std::size_t m : members)
        if (in_tree[m])
          for (const auto& [w, j] : adjacent[m])
            if (!in_tree[j] && w < best) {
              best = w;
              from = m;
              to = j;
            }
      in_tree[to] = 1;
      if (normals[to].dot(normals[from]) < 0) normals[to] = -normals[to];
    }
  }
  return normals;
}

TEST(NormalOrientation, KruskalForestEqualsPrimsTreesOnRandomGraphs) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> g(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    PointCloud cloud;
    for (int i = 0; i < 80; ++i) {
      // Two clusters, so that some graphs have two components.
      const double offset = i < 40 ? 0.0 : (trial % 2 ? 10.0 : 0.5);
      cloud.positions.emplace_back(g(rng) + offset, g(rng), g(rng));
      cloud.normals.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
    }
    const NeighbourGraph graph = nearestNeighbourGraph(cloud.positions, 4);
    // Ties in the float weights would let the two algorithms pick different
    // (equally good) trees; such draws are skipped.
    std::vector<float> weights;
    for (std::size_t i = 0; i < cloud.size(); ++i)
      for (std::size_t s = 0; s < graph.slots; ++s) {
        const std::size_t j = graph.neighbours[i * graph.slots + s];
        if (j < i) continue;
        weights.push_back(static_cast<float>(1.0 - std::abs(cloud.normals[i].dot(cloud.normals[j]))));
      }
    std::sort(weights.begin(), weights.end());
    if (std::adjacent_find(weights.begin(), weights.end()) != weights.end()) continue;
    const std::vector<Eigen::Vector3d> expected = orientedByPrim(cloud, graph);
    orientNormalsOverGraph(cloud, graph);
    for (std::size_t i = 0; i < cloud.size(); ++i) ASSERT_EQ(cloud.normals[i], expected[i]) << "trial " << trial << ", point " << i;
    ++compared;
  }
  EXPECT_GE(compared, 30);
}

TEST(NormalOrientation, AZeroNormalPassesItsParentsOrientationOn) {
  // A chain 0 - 1 - 2 whose middle normal is zero: 2 must agree with 0.
  PointCloud cloud;
  for (int i = 0; i < 3; ++i) cloud.positions.emplace_back(i, 0, 0);
  cloud.normals = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ()};
  NeighbourGraph chain;
  chain.slots = 1;
  chain.neighbours = {1, 2, 1};
  orientNormalsOverGraph(cloud, chain);
  EXPECT_EQ(cloud.normals[1], Eigen::Vector3d::Zero());
  EXPECT_GT(cloud.normals[0].dot(cloud.normals[2]), 0.0);
}

TEST(NormalOrientation, GraphOfTheWrongSizeIsAnError) {
  Torus t = randomTorus(100, 0.08, 0.03, 9);
  NeighbourGraph graph;
  graph.slots = 3;
  graph.neighbours.assign(10, 0);
  EXPECT_THROW(orientNormalsOverGraph(t.cloud, graph), InputError);
}

TEST(NormalOrientation, SmoothingOrientsTheTorusLikeTheStandaloneCall) {
  // The smoothing pass hands its windows' nearest points to the orientation.
  Torus t = randomTorus(20000, 0.08, 0.03, 10);
  PointCloud smoothed = t.cloud;
  SmoothingParameters params;
  params.radius = Length::metres(0.006);
  smoothPointCloud(smoothed, params);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < t.cloud.size(); ++i) wrong += smoothed.normals[i].dot(t.truth[i]) < 0 ? 1 : 0;
  EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace icrkit::ndt
