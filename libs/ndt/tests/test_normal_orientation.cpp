#include <icrkit/ndt/normal_orientation.hpp>
#include <icrkit/ndt/smoothing.hpp>

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

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
  params.radius = 0.006;
  smoothPointCloud(smoothed, params);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < t.cloud.size(); ++i) wrong += smoothed.normals[i].dot(t.truth[i]) < 0 ? 1 : 0;
  EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace icrkit::ndt
