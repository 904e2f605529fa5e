#include "registration/miss_bounds.hpp"

#include <icrkit/core/kd_tree.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace icrkit::reconstruction {
namespace {

// Targets on a 10 cm patch of plane z = 0 (1 mm grid, jittered); sources
// scattered 0-15 mm above and beside it, so that many find nothing within
// the pairing distance.
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

TEST(MissBounds, ReturnsWhatAFreshSearchReturnsWhileTheSourcesMove) {
  // Seeds 1-3 at the origin; seed 4 25 m away, where a float's rounding
  // (1e-6 m) is as large as a fixed slack would be.
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    Scene scene = makeScene(seed);
    if (seed == 4) {
      const Eigen::Vector3d offset(25.0, -18.0, 21.0);
      for (Eigen::Vector3d& p : scene.targets) p += offset;
      for (Eigen::Vector3d& p : scene.sources) p += offset;
    }
    const KdTree tree(scene.targets);
    std::size_t searched = 0, calls = 0;
    auto search = [&](const Eigen::Vector3d& q, double radius) {
      ++searched;
      return tree.nearestWithin(q, radius);
    };
    MissBounds bounds(scene.sources.size());
    std::mt19937 rng(seed + 100);
    std::normal_distribution<double> step(0.0, 0.0004), turn(0.0, 0.004);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
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
        for (std::size_t k = 0; k < scene.sources.size(); ++k) {
          const Eigen::Vector3d q = pose * scene.sources[k];
          ++calls;
          ASSERT_EQ(bounds.nearestWithin(k, q, max_distance, 2.0 * max_distance, scene.targets, search),
                    tree.nearestWithin(q, max_distance))
              << "seed " << seed << " source " << k << " distance " << max_distance << " iteration " << it;
        }
      }
    }
    // Most sources are far from the patch: most calls must not search.
    EXPECT_LT(searched, calls / 2) << "seed " << seed;
  }
}

TEST(MissBounds, ASourceOnATargetIsFoundAndOneBeyondReachIsNot) {
  const std::vector<Eigen::Vector3d> targets{{0, 0, 0}, {0.01, 0, 0}};
  const KdTree tree(targets);
  auto search = [&](const Eigen::Vector3d& q, double radius) { return tree.nearestWithin(q, radius); };
  MissBounds bounds(2);
  EXPECT_EQ(bounds.nearestWithin(0, Eigen::Vector3d(0.0098, 0, 0), 0.001, 0.002, targets, search), 1);
  // 5 mm from both: nothing within 1 mm, and the bound remembers 2 mm.
  EXPECT_EQ(bounds.nearestWithin(1, Eigen::Vector3d(0.005, 0.0, 0.005), 0.001, 0.002, targets, search), -1);
  // Moved 0.5 mm: still at least 1.5 mm away, no search needed; moved onto
  // a target: found.
  EXPECT_EQ(bounds.nearestWithin(1, Eigen::Vector3d(0.005, 0.0, 0.0045), 0.001, 0.002, targets, search), -1);
  EXPECT_EQ(bounds.nearestWithin(1, Eigen::Vector3d(0.0, 0.0, 0.0002), 0.001, 0.002, targets, search), 0);
  // Exactly at the pairing distance: not within it (strict, as the tree).
  EXPECT_EQ(bounds.nearestWithin(0, Eigen::Vector3d(0.0, 0.0, 0.0015), 0.0015, 0.003, targets, search),
            tree.nearestWithin(Eigen::Vector3d(0.0, 0.0, 0.0015), 0.0015));
}

}  // namespace
}  // namespace icrkit::reconstruction
