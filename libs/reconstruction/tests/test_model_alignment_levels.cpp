#include "registration/model_alignment_levels.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace icrkit::reconstruction {
namespace {

TEST(ModelAlignmentLevels, TheSpreadOfABoxIsItsLongestSidesStandardDeviation) {
  // Uniform on a 0.12 x 0.04 x 0.02 m box, turned and 5 m from the origin:
  // the sd along its long side is 0.12 / sqrt(12).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const Eigen::Isometry3d place =
      Eigen::Translation3d(5.0, -3.0, 1.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  std::vector<Eigen::Vector3d> box;
  for (int k = 0; k < 40000; ++k) box.push_back(place * Eigen::Vector3d(0.12 * u(rng), 0.04 * u(rng), 0.02 * u(rng)));
  EXPECT_NEAR(largestSpread(box), 0.12 / std::sqrt(12.0), 5e-4);
}

TEST(ModelAlignmentLevels, TheObjectsSpreadIsTheMedianViewsAndIgnoresWhereTheViewsAre) {
  // Three views of lines 2, 4 and 10 cm long, each far from the others: the
  // median view's spread (4 cm / sqrt(12)), not the union's.
  auto line = [](double length, const Eigen::Vector3d& at) {
    std::vector<Eigen::Vector3d> v;
    for (int k = 0; k <= 1000; ++k) v.push_back(at + Eigen::Vector3d(length * (k / 1000.0 - 0.5), 0, 0));
    return v;
  };
  const std::vector<std::vector<Eigen::Vector3d>> views{
      line(0.02, {0, 0, 1}), line(0.10, {0.3, 0, 1}), line(0.04, {-2, 1, 1}), {Eigen::Vector3d(1, 1, 1)}, {}};
  EXPECT_NEAR(medianViewSpread({&views[0], &views[1], &views[2], &views[3], &views[4]}), 0.04 / std::sqrt(12.0), 1e-4);
  // Two views: the mean of the two.
  EXPECT_NEAR(medianViewSpread({&views[0], &views[2]}), 0.03 / std::sqrt(12.0), 1e-4);
}

TEST(ModelAlignmentLevels, TooFewPointsHaveNoSpread) {
  EXPECT_EQ(largestSpread({Eigen::Vector3d(1, 2, 3)}), 0.0);
  EXPECT_EQ(largestSpread({}), 0.0);
  const std::vector<Eigen::Vector3d> one{Eigen::Vector3d(1, 2, 3)}, none;
  EXPECT_EQ(medianViewSpread({&one, &none}), 0.0);
}

TEST(ModelAlignmentLevels, CellsTooLargeForTheObjectAreLeftOutButNeverTheFinest) {
  const std::vector<double> levels{0.06, 0.04, 0.02, 0.01};
  // A bunny (45 mm) and a cup (32 mm): every level; a compact toy (28 mm): from 4 cm.
  EXPECT_EQ(modelAlignmentLevels(levels, 2.0, 0.045), levels);
  EXPECT_EQ(modelAlignmentLevels(levels, 2.0, 0.032), levels);
  EXPECT_EQ(modelAlignmentLevels(levels, 2.0, 0.028), (std::vector<double>{0.04, 0.02, 0.01}));
  // A tiny object: only the finest.
  EXPECT_EQ(modelAlignmentLevels(levels, 2.0, 0.001), (std::vector<double>{0.01}));
  // Switched off, or nothing measured: every level.
  EXPECT_EQ(modelAlignmentLevels(levels, 0.0, 0.001), levels);
  EXPECT_EQ(modelAlignmentLevels(levels, 2.0, 0.0), levels);
  EXPECT_TRUE(modelAlignmentLevels({}, 2.0, 0.03).empty());
}

}  // namespace
}  // namespace icrkit::reconstruction
