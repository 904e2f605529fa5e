#include "meshing/layer_thinning.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <tuple>

namespace icrkit::reconstruction {
namespace {

TEST(LayerThinning, NoisyPlaneMeasuresItsNoise) {
  // A 5 cm sheet at 0.5 mm with Gaussian noise of 0.3 mm across it.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 3e-4);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) points.emplace_back(i * 5e-4, j * 5e-4, noise(rng));
  EXPECT_NEAR(layerThickness(points, {}, 3e-3), 3e-4, 0.4e-4);
}

TEST(LayerThinning, CleanCurvedSurfaceMeasuresAboutZero) {
  // A sphere of 2 cm sampled at about 1 mm, windows of 6 mm: a plane fit
  // would see 0.3 mm of curvature, the quadric sees none.
  std::vector<Eigen::Vector3d> points;
  const double radius = 0.02;
  for (int i = 1; i < 63; ++i) {
    const double theta = M_PI * i / 63;
    const int around = std::max(1, static_cast<int>(std::round(2 * M_PI * radius * std::sin(theta) / 1e-3)));
    for (int j = 0; j < around; ++j) {
      const double phi = 2 * M_PI * j / around;
      points.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                          radius * std::cos(theta));
    }
  }
  EXPECT_LT(layerThickness(points, {}, 6e-3), 2e-5);
}

TEST(LayerThinning, SkippedPointsAndTooSparseWindows) {
  std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(layerThickness(points, {}, 0.1), 0.0);  // no window holds 12 points
  EXPECT_EQ(layerThickness(points, {}, 0.0), 0.0);
}

TEST(LayerThinning, OnePointPerCubeNearestTheCentroid) {
  // Two cubes of 1 cm: three points in the first (the middle one is nearest
  // their centroid), one in the second, one skipped.
  const std::vector<Eigen::Vector3d> points{
      {0.001, 0.001, 0.001}, {0.005, 0.005, 0.005}, {0.008, 0.009, 0.008}, {0.015, 0.001, 0.001}, {0.016, 0.002, 0.002}};
  const std::vector<std::uint8_t> skip{0, 0, 0, 0, 1};
  const std::vector<std::uint8_t> keep = thinToCells(points, skip, 0.01);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 1, 0, 1, 0}));
  // Cubes smaller than the spacing keep everything not skipped.
  EXPECT_EQ(thinToCells(points, skip, 1e-4), (std::vector<std::uint8_t>{1, 1, 1, 1, 0}));
}

}  // namespace
}  // namespace icrkit::reconstruction
