#include "registration/nearest_tracker.hpp"

#include <icrkit/core/kd_tree.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace icrkit::reconstruction {
namespace {

// Targets on a 10 cm patch of plane z = 0 (1 mm grid, jittered); sources
// scattered 0-15 mm above and beside it, so that many find nothing within
// the pairing distance and many do.
struct Scene {
  std::vector<Eigen::Vector3d> targets, sources;
};

Scene makeScene(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.0003, 0.0003), across(-0.06, 0.06), up(0.0, 0.015);
  Scene s;
  for (int x = -50; x <= 50; ++x)
    for (int y = -50; y <= 50; ++y) s.targets.emplace_back(0.001 * x + jitter(rng), 0.001 * y + jitter(rng), jitter(rng));
  for (int k = 0; k < 2000; ++k) s.sources.emplace_back(across(rng), across(rng), up(rng));
  return s;
}

// The tree, counting the searches the tracker asks of it.
struct CountingTree {
  const KdTree& tree;
  mutable std::size_t nearest = 0, within = 0;
  long nearestWithin(const Eigen::Vector3d& q, double radius) const {
    ++nearest;
    return tree.nearestWithin(q, radius);
  }
  void indicesWithinRadiusInTreeOrder(const Eigen::Vector3d& q, double radius, std::vector<std::size_t>& out) const {
    ++within;
    tree.indicesWithinRadiusInTreeOrder(q, radius, out);
  }
};

TEST(NearestTracker, VisitsWhatAFreshSearchFindsWhileTheSourcesMove) {
  // Seeds 1-3 at the origin; seed 4 25 m away, where a float's rounding
  // (1e-6 m) is as large as a fixed slack would be. Steps of half a
  // millimetre (most sources keep their surroundings) and of two (most
  // leave them).
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    for (double scale : {1.0, 4.0}) {
      Scene scene = makeScene(seed);
      if (seed == 4) {
        const Eigen::Vector3d offset(25.0, -18.0, 21.0);
        for (Eigen::Vector3d& p : scene.targets) p += offset;
        for (Eigen::Vector3d& p : scene.sources) p += offset;
      }
      const KdTree tree(scene.targets);
      const CountingTree counting{tree};
      NearestTracker<CountingTree> tracker(scene.sources, {});
      std::mt19937 rng(seed + 100);
      std::normal_distribution<double> step(0.0, 0.0004 * scale), turn(0.0, 0.004 * scale);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      std::size_t calls = 0, hits = 0;
      // Coarse to fine pairing distances, as an ICP's stages, while the pose
      // drifts by about half a millimetre and a quarter degree per call.
      for (double max_distance : {0.006, 0.003, 0.0015}) {
        for (int it = 0; it < 15; ++it) {
          // Turned about the patch's centre, wherever it lies.
          const Eigen::Vector3d centre = scene.targets[scene.targets.size() / 2];
          Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
          delta.linear() = (Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitY()))
                               .toRotationMatrix();
          delta.translation() = centre - delta.linear() * centre + Eigen::Vector3d(step(rng), step(rng), step(rng));
          pose = delta * pose;
          std::vector<long> expected(scene.sources.size(), -1), got(scene.sources.size(), -1);
          for (std::size_t k = 0; k < scene.sources.size(); ++k)
            expected[k] = tree.nearestWithin(pose * scene.sources[k], max_distance);
          std::size_t last = 0;
          bool ascending = true;
          tracker.forEachNearest(scene.sources, pose, max_distance, scene.targets, counting,
                                 [&](std::size_t k, const Eigen::Vector3d& q, long t) {
                                   ascending = ascending && (k >= last);
                                   last = k;
                                   got[k] = t;
                                   EXPECT_EQ(q, pose * scene.sources[k]);
                                 });
          ASSERT_TRUE(ascending);
          for (std::size_t k = 0; k < scene.sources.size(); ++k)
            ASSERT_EQ(got[k], expected[k]) << "seed " << seed << " scale " << scale << " source " << k
                                           << " distance " << max_distance << " iteration " << it;
          calls += scene.sources.size();
          hits += static_cast<std::size_t>(std::count_if(expected.begin(), expected.end(), [](long t) { return t >= 0; }));
        }
      }
      EXPECT_GT(hits, calls / 20) << "seed " << seed;
      // Small steps: the tree is asked for a fraction of the sources, hits
      // included (large ones only check the answers).
      if (scale == 1.0) {
        EXPECT_LT(counting.nearest + counting.within, calls / 2) << "seed " << seed;
      }
    }
  }
}

TEST(NearestTracker, ASourceOnATargetIsFoundAndOneBeyondReachIsNot) {
  const std::vector<Eigen::Vector3d> targets{{0, 0, 0}, {0.01, 0, 0}};
  const KdTree tree(targets);
  std::vector<Eigen::Vector3d> sources{{0.0098, 0, 0}, {0.005, 0.0, 0.005}};
  NearestTracker<KdTree>::Parameters params;
  params.block_size = 1;
  NearestTracker<KdTree> tracker(sources, params);
  double lower = 0.0;
  EXPECT_EQ(tracker.nearestWithin(0, sources[0], 0.001, targets, tree, lower), 1);
  EXPECT_NEAR(lower, 0.0002, 1e-12);
  // A hit that slid 0.1 mm onto its target: its surroundings
  // (within 0.2 + 2 x 0.25 mm of where it was found) hold the answer.
  EXPECT_EQ(tracker.nearestWithin(0, Eigen::Vector3d(0.0099, 0, 0), 0.001, targets, tree, lower), 1);
  EXPECT_NEAR(lower, 0.0001, 1e-12);
  // 5 mm from both: nothing within 1 mm, and the bound remembers 2 mm.
  EXPECT_EQ(tracker.nearestWithin(1, sources[1], 0.001, targets, tree, lower), -1);
  EXPECT_NEAR(lower, 0.002, 1e-12);
  // Moved 0.5 mm: still at least 1.5 mm away, no search needed; moved onto
  // a target: found.
  EXPECT_EQ(tracker.nearestWithin(1, Eigen::Vector3d(0.005, 0.0, 0.0045), 0.001, targets, tree, lower), -1);
  EXPECT_GT(lower, 0.0014);
  EXPECT_EQ(tracker.nearestWithin(1, Eigen::Vector3d(0.0, 0.0, 0.0002), 0.001, targets, tree, lower), 0);
  // Exactly at the pairing distance: not within it (strict, as the tree).
  EXPECT_EQ(tracker.nearestWithin(0, Eigen::Vector3d(0.0, 0.0, 0.0015), 0.0015, targets, tree, lower),
            tree.nearestWithin(Eigen::Vector3d(0.0, 0.0, 0.0015), 0.0015));
}

TEST(NearestTracker, ATieBetweenLeavesGivesWhatTheTreeGives) {
  // Targets 0..15 on a line; the source first found 8 from 7.6, then sits
  // at 7.5, equally near 7 and 8, which the tree's leaves hold apart.
  std::vector<Eigen::Vector3d> targets;
  for (int x = 0; x < 16; ++x) targets.emplace_back(x, 0, 0);
  const KdTree tree(targets);
  const std::vector<Eigen::Vector3d> sources{{0, 0, 0}};
  for (int m = 0; m + 1 < 16; ++m) {
    NearestTracker<KdTree> tracker(sources, {});
    Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
    long found = -2;
    auto visit = [&](std::size_t, const Eigen::Vector3d&, long t) { found = t; };
    placement.translation() = Eigen::Vector3d(m + 0.6, 0, 0);
    tracker.forEachNearest(sources, placement, 2.0, targets, tree, visit);
    EXPECT_EQ(found, m + 1);
    placement.translation() = Eigen::Vector3d(m + 0.5, 0, 0);
    tracker.forEachNearest(sources, placement, 2.0, targets, tree, visit);
    EXPECT_EQ(found, tree.nearestWithin(placement.translation(), 2.0)) << "midpoint " << m;
    EXPECT_EQ(found, m);
  }
}

TEST(NearestTracker, ANonPositivePairingDistanceFindsNothingAndLeavesTheBounds) {
  const std::vector<Eigen::Vector3d> targets{{5, 0, 0}};
  const KdTree tree(targets);
  const std::vector<Eigen::Vector3d> sources{{5, 0, 0}};
  NearestTracker<KdTree> tracker(sources, {});
  long found = -2;
  auto visit = [&](std::size_t, const Eigen::Vector3d&, long t) { found = t; };
  tracker.forEachNearest(sources, Eigen::Isometry3d::Identity(), -1.0, targets, tree, visit);
  EXPECT_EQ(found, -2);
  tracker.forEachNearest(sources, Eigen::Isometry3d::Identity(), 1.0, targets, tree, visit);
  EXPECT_EQ(found, 0);
}

TEST(NearestTracker, EquallyNearTargetsGiveTheLowestIndexAsTheTreeDoes) {
  // Four targets at the same distance from the source's later places.
  const std::vector<Eigen::Vector3d> targets{{0.001, 0, 0}, {-0.001, 0, 0}, {0, 0.001, 0}, {0, -0.001, 0}};
  const KdTree tree(targets);
  const std::vector<Eigen::Vector3d> sources{{0.0001, 0, 0}};
  NearestTracker<KdTree> tracker(sources, {});
  double lower = 0.0;
  EXPECT_EQ(tracker.nearestWithin(0, sources[0], 0.004, targets, tree, lower), 0);
  const Eigen::Vector3d centre(0, 0, 0.0001);
  EXPECT_EQ(tracker.nearestWithin(0, centre, 0.004, targets, tree, lower), tree.nearestWithin(centre, 0.004));
}

}  // namespace
}  // namespace icrkit::reconstruction
