// Variance component estimation: graphs whose edges carry noise of known
// sigma, stated wrongly.

#include <icrkit/reconstruction/registration/pose_graph_variance.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace icrkit::reconstruction {
namespace {

Eigen::Isometry3d noisy(const Eigen::Isometry3d& pose, std::mt19937_64& rng, double sigma_t, double sigma_r) {
  std::normal_distribution<double> g;
  Vector6d d;
  for (int k = 0; k < 3; ++k) d(k) = sigma_t * g(rng);
  for (int k = 3; k < 6; ++k) d(k) = sigma_r * g(rng);
  return poseGraphRetract(pose, d);
}

// A ring of scans: absolute priors (true sigma 3 mm / 0.01 rad, stated
// 6 mm / 0.02 rad) and pairs to the next two scans (true 0.5 mm / 0.002 rad,
// stated right).
struct Ring {
  PoseGraph graph;
  std::vector<int> group;
};

Ring makeRing(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    const double a = 2 * M_PI * i / n;
    t.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.translation() = 0.6 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.2);
    truth.push_back(t);
  }
  Ring r;
  r.graph.poses = truth;
  r.graph.poses.push_back(Eigen::Isometry3d::Identity());  // world
  r.graph.fixed = {static_cast<std::size_t>(n)};
  for (int i = 0; i < n; ++i) {
    PoseGraphEdge prior;
    prior.from = static_cast<std::size_t>(n);
    prior.to = static_cast<std::size_t>(i);
    prior.measurement = noisy(truth[i], rng, 0.003, 0.01);
    prior.information = poseGraphInformation(0.006, 0.02);
    prior.robust = false;
    r.graph.edges.push_back(prior);
    r.group.push_back(1);
    for (int step = 1; step <= 2; ++step) {
      const int j = (i + step) % n;
      PoseGraphEdge pair;
      pair.from = static_cast<std::size_t>(i);
      pair.to = static_cast<std::size_t>(j);
      pair.measurement = noisy(truth[i].inverse() * truth[j], rng, 0.0005, 0.002);
      pair.information = poseGraphInformation(0.0005, 0.002);
      pair.robust = false;
      r.graph.edges.push_back(pair);
      r.group.push_back(0);
    }
  }
  for (int i = 0; i < n; ++i) r.graph.poses[i] = r.graph.edges[3 * i].measurement;  // start at the priors
  return r;
}

TEST(PoseGraphVariance, RecoversTheRatioOfTrueToStatedVariance) {
  Ring ring = makeRing(120, 3);
  PoseGraphResult solved = optimisePoseGraph(ring.graph);
  // Iterated: each group rescaled by its estimate, solved again.
  double prior_factor = 1.0, pair_factor = 1.0;
  for (int round = 0; round < 8; ++round) {
    const auto c = estimateVarianceComponents(ring.graph, solved, ring.group, 2);
    ASSERT_TRUE(c.has_value());
    EXPECT_GT((*c)[0].redundancy, 0.0);
    EXPECT_LT((*c)[1].redundancy, 6.0 * 120);
    pair_factor *= (*c)[0].variance_factor;
    prior_factor *= (*c)[1].variance_factor;
    for (std::size_t e = 0; e < ring.graph.edges.size(); ++e)
      ring.graph.edges[e].information /= (*c)[static_cast<std::size_t>(ring.group[e])].variance_factor;
    solved = optimisePoseGraph(ring.graph);
  }
  // Stated 2x the true sigma: variance factor 1/4; the pairs were stated right.
  EXPECT_NEAR(prior_factor, 0.25, 0.05);
  EXPECT_NEAR(pair_factor, 1.0, 0.12);
}

TEST(PoseGraphVariance, TooLargeOrUngroupedGraphsGiveNothingOrDefaults) {
  const Ring ring = makeRing(30, 4);
  const PoseGraphResult solved = optimisePoseGraph(ring.graph);
  EXPECT_FALSE(estimateVarianceComponents(ring.graph, solved, ring.group, 2, 10).has_value());
  EXPECT_FALSE(estimateVarianceComponents(ring.graph, solved, {1, 2}, 2).has_value());
  const std::vector<int> none(ring.graph.edges.size(), -1);
  const auto c = estimateVarianceComponents(ring.graph, solved, none, 1);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ((*c)[0].edges, 0u);
  EXPECT_DOUBLE_EQ((*c)[0].variance_factor, 1.0);
}

}  // namespace
}  // namespace icrkit::reconstruction
