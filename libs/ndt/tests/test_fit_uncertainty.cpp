// The recorded uncertainty of a plane fit against the true spread, on planes
// with known Gaussian noise: the sigmas the smoothing layer and the raw normal
// estimation write must match how far their normals and positions really are
// from the truth (within 20 %), or uncertainty-aware ICRs guard the wrong margin.

#include "synthetic_surfaces.hpp"

#include <icrkit/ndt/fit_uncertainty.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/ndt/smoothing.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace icrkit::ndt {
namespace {

struct Spread {
  double true_normal = 0, recorded_normal = 0;      // RMS angle, radians
  double true_position = 0, recorded_position = 0;  // RMS along z, metres
};

// Root mean squares over the points farther than `margin` from the border.
Spread measure(const test::SyntheticCloud& s, const PointCloud& fitted, double margin) {
  const Attribute* normal_sigma = fitted.attributes.find(kNormalSigmaAttribute);
  const Attribute* position_sigma = fitted.attributes.find(kPositionSigmaAttribute);
  EXPECT_NE(normal_sigma, nullptr);
  EXPECT_NE(position_sigma, nullptr);
  Spread out;
  if (!normal_sigma || !position_sigma) return out;
  std::size_t n = 0;
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    if (s.edge_distance[i] <= margin) continue;
    const double angle = std::acos(std::min(1.0, std::abs(fitted.normals[i].normalized().z())));
    out.true_normal += angle * angle;
    out.recorded_normal += normal_sigma->values[i] * normal_sigma->values[i];
    out.true_position += fitted.positions[i].z() * fitted.positions[i].z();
    out.recorded_position += position_sigma->values[i] * position_sigma->values[i];
    ++n;
  }
  EXPECT_GT(n, 1000u);
  for (double* v : {&out.true_normal, &out.recorded_normal, &out.true_position, &out.recorded_position})
    *v = std::sqrt(*v / static_cast<double>(n));
  return out;
}

void expectWithin20Percent(double recorded, double truth, const std::string& what) {
  ::testing::Test::RecordProperty(what, std::to_string(recorded / truth));
  EXPECT_GT(recorded, 0.8 * truth) << what << ": recorded " << recorded << ", true spread " << truth;
  EXPECT_LT(recorded, 1.2 * truth) << what << ": recorded " << recorded << ", true spread " << truth;
}

struct Case {
  double sigma;          // noise along the normal, metres
  double radius_factor;  // window radius in spacings
};

class PlaneUncertainty : public ::testing::TestWithParam<Case> {};

TEST_P(PlaneUncertainty, SmoothingRecordsTheSpreadOfItsNormalsAndPositions) {
  const Case c = GetParam();
  const double spacing = 0.001;
  const test::SyntheticCloud s = test::makePlane(90, spacing, c.sigma, 19);
  PointCloud smoothed = s.cloud;
  SmoothingParameters params;
  params.radius = Length::spacings(c.radius_factor);
  params.preselection.rule = PreselectionRule::None;
  const SmoothingReport summary = smoothPointCloud(smoothed, params);
  const Spread spread = measure(s, smoothed, summary.radius_m + spacing);
  expectWithin20Percent(spread.recorded_normal, spread.true_normal, "smoothed normal");
  expectWithin20Percent(spread.recorded_position, spread.true_position, "smoothed position");
}

TEST_P(PlaneUncertainty, RawNormalEstimationRecordsTheSpreadOfItsNormalsAndThePointsNoise) {
  const Case c = GetParam();
  const double spacing = 0.001;
  const test::SyntheticCloud s = test::makePlane(90, spacing, c.sigma, 23);
  PointCloud raw = s.cloud;
  NormalEstimationParameters params;
  params.radius = Length::spacings(c.radius_factor);
  const NormalEstimationReport summary = estimateNormals(raw, params);
  const Spread spread = measure(s, raw, summary.radius_m + spacing);
  expectWithin20Percent(spread.recorded_normal, spread.true_normal, "raw normal");
  expectWithin20Percent(spread.recorded_position, spread.true_position, "raw position");
  expectWithin20Percent(spread.recorded_position, c.sigma, "raw position against the noise");
}

INSTANTIATE_TEST_SUITE_P(NoiseAndWindow, PlaneUncertainty,
                         ::testing::Values(Case{0.0001, 3.0}, Case{0.0003, 4.0}, Case{0.0005, 4.0}, Case{0.0003, 6.0}));

TEST(FitUncertainty, ADegenerateWindowKnowsNothing) {
  const Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  // Three points: the plane takes every degree of freedom, no residual is left.
  FitUncertainty u = planeFitUncertainty(Eigen::Vector3d(1e-6, 1e-6, 0), axes, 3, Eigen::Vector3d::Zero(), 0.004,
                                         FittedPoint::Projected);
  EXPECT_DOUBLE_EQ(u.normal_sigma, M_PI / 2);
  EXPECT_DOUBLE_EQ(u.position_sigma, 0.004);
  // A line of points (l2 = 0) has no plane.
  u = planeFitUncertainty(Eigen::Vector3d(1e-6, 0, 0), axes, 10, Eigen::Vector3d::Zero(), 0.004, FittedPoint::Measured);
  EXPECT_DOUBLE_EQ(u.normal_sigma, M_PI / 2);
}

TEST(FitUncertainty, KnownAnswerOfTheModel) {
  // k = 13, l1 = l2 = 4e-6, l3 = 1e-8: s^2 = 1e-8 * 13 / 10 = 1.3e-8.
  const Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d values(4e-6, 4e-6, 1e-8);
  const double noise = 1.3e-8;
  FitUncertainty u = planeFitUncertainty(values, axes, 13, Eigen::Vector3d(0.002, 0, 0), 0.01, FittedPoint::Projected);
  EXPECT_NEAR(u.normal_sigma, std::sqrt(noise / 13 * 2 / 4e-6), 1e-12);
  EXPECT_NEAR(u.position_sigma, std::sqrt(noise / 13 * (1 + 4e-6 / 4e-6)), 1e-12);
  u = planeFitUncertainty(values, axes, 13, Eigen::Vector3d(0.002, 0, 0), 0.01, FittedPoint::Measured);
  EXPECT_NEAR(u.position_sigma, std::sqrt(noise), 1e-12);
}

}  // namespace
}  // namespace icrkit::ndt
