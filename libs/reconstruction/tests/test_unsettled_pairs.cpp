// Which pairs of a multiway round its own pose graph made stale
// (registration/unsettled_pairs.hpp), on four views with known moves.

#include "registration/unsettled_pairs.hpp"
#include "registration/view_pairs.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <vector>

namespace icrkit::reconstruction {
namespace {

constexpr double kMinInliers = 0.15;  // min_icp_inlier_fraction's default
constexpr double kMove = 0.003;

PairRegistrationRecord pairOf(std::size_t from, std::size_t to, bool accepted, double inliers) {
  PairRegistrationRecord pair;
  pair.from = from;
  pair.to = to;
  pair.accepted = accepted;
  pair.icp_inlier_fraction = inliers;
  return pair;
}

Eigen::Isometry3d shifted(double x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, 0, 0);
  return pose;
}

// Views 0-1 and 2-3 are linked by accepted pairs; the graph then moves
// view 2 by 6 mm and view 3 by 2 mm along x (the pair 2-3 makes them one
// component whatever they did).
struct Round {
  std::vector<PairRegistrationRecord> pairs{
      pairOf(0, 1, true, 0.9),    // accepted
      pairOf(2, 3, true, 0.9),    // accepted
      pairOf(1, 2, false, 0.05),  // too little overlap, bridging, its views moved 6 mm apart: unsettled
      pairOf(1, 3, false, 0.0),   // too little overlap, bridging, but moved only 2 mm
      pairOf(0, 2, false, 0.8),   // bridging and moved 6 mm, but rejected for another reason (a slide)
      pairOf(2, 3, false, 0.1),   // too little overlap, moved 4 mm, but its views are linked already
  };
  std::vector<Eigen::Isometry3d> before{shifted(0), shifted(0.1), shifted(0.2), shifted(0.3)};
  std::vector<Eigen::Isometry3d> after{shifted(0), shifted(0.1), shifted(0.206), shifted(0.302)};
  std::vector<std::optional<Eigen::Vector3d>> centroids{Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0, 0, 0.5),
                                                        Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0, 0, 0.5)};
};

TEST(UnsettledPairs, OnlyABridgingPairTheICPCouldNotReachWhoseViewsMovedApartIsStale) {
  const Round r;
  const std::vector<std::size_t> stale = unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, kMove);
  EXPECT_EQ(stale, std::vector<std::size_t>({2}));
  // A looser move threshold lets none through; a tighter one also the 2 mm pair.
  EXPECT_TRUE(unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, 0.007).empty());
  EXPECT_EQ(unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, 0.001),
            std::vector<std::size_t>({2, 3}));
}

TEST(UnsettledPairs, MovingEveryViewTogetherMakesNothingStale) {
  Round r;
  // A rigid motion of the whole set (15 deg about z and 4 cm): no view
  // moved relative to another, however far each went.
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.26, Eigen::Vector3d::UnitZ()));
  motion.pretranslate(Eigen::Vector3d(0.04, 0, 0));
  for (std::size_t i = 0; i < r.before.size(); ++i) r.after[i] = motion * r.before[i];
  EXPECT_TRUE(unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, kMove).empty());
}

TEST(UnsettledPairs, AViewWithoutPointsIsSkipped) {
  Round r;
  r.centroids[2].reset();
  EXPECT_TRUE(unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, kMove).empty());
}

TEST(UnsettledPairs, LinkedViewsAreTheAcceptedPairsComponents) {
  const Round r;
  DisjointSets linked = linkedViews(r.pairs, 5);
  EXPECT_EQ(linked.find(0), linked.find(1));
  EXPECT_EQ(linked.find(2), linked.find(3));
  EXPECT_NE(linked.find(1), linked.find(2));
  EXPECT_NE(linked.find(4), linked.find(0));  // a view in no pair is alone
}

TEST(UnsettledPairs, MismatchedInputIsRefused) {
  Round r;
  r.after.pop_back();
  EXPECT_THROW(unsettledPairs(r.pairs, r.before, r.after, r.centroids, kMinInliers, kMove), std::invalid_argument);
  Round beyond;
  beyond.pairs.push_back(pairOf(1, 7, false, 0.0));
  EXPECT_THROW(unsettledPairs(beyond.pairs, beyond.before, beyond.after, beyond.centroids, kMinInliers, kMove),
               std::invalid_argument);
}

}  // namespace
}  // namespace icrkit::reconstruction
