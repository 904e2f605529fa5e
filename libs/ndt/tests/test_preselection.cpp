// The preselection rules on clouds whose uncertain points are known: a
// plane with a flying point and a step, a plane whose noise doubles
// halfway, and the rules' arithmetic on hand-made statistics.

#include "synthetic_surfaces.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/ndt/preselection_record.hpp>
#include <icrkit/ndt/smoothing.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace icrkit::ndt {
namespace {

constexpr double kSpacing = 0.001;

PreselectionParameters withRule(PreselectionRule rule) {
  PreselectionParameters params;
  params.rule = rule;
  return params;
}

PointCloud smoothedWith(PointCloud cloud, PreselectionRule rule) {
  SmoothingParameters params;
  params.preselection.rule = rule;
  smoothPointCloud(cloud, params);
  return cloud;
}

// A 120 x 120 grid (1 mm, noise 0.2 mm) whose half x >= 60 mm is raised by a
// 3 mm step, plus one flying point 15 mm above the middle.
struct StepPlane {
  PointCloud cloud;
  std::vector<double> step_distance;  // |x - 60 mm|
  std::size_t flying = 0;
};

StepPlane makeStepPlane() {
  StepPlane s;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 0.0002);
  for (int i = 0; i < 120; ++i)
    for (int j = 0; j < 120; ++j) {
      const double x = i * kSpacing, y = j * kSpacing;
      const double z = (x >= 0.0595 ? 0.003 : 0.0) + gauss(rng);
      s.cloud.positions.emplace_back(x, y, z);
      s.step_distance.push_back(std::abs(x - 0.0595));
    }
  s.flying = s.cloud.size();
  s.cloud.positions.emplace_back(0.03, 0.06, 0.015);
  s.step_distance.push_back(1.0);
  return s;
}

TEST(Preselection, DefaultRuleExcludesTheFlyingPointAndTheStepAndKeepsThePlane) {
  const StepPlane s = makeStepPlane();
  const PointCloud out = smoothedWith(s.cloud, PreselectionRule::Robust);
  std::size_t at_step = 0, at_step_excluded = 0, plane = 0, plane_excluded = 0;
  for (std::size_t i = 0; i < s.flying; ++i) {
    const Eigen::Vector3d& p = s.cloud.positions[i];
    const bool border = p.x() < 0.005 || p.y() < 0.005 || p.x() > 0.114 || p.y() > 0.114;
    if (s.step_distance[i] < 0.0015) {
      ++at_step;
      at_step_excluded += out.flag("excluded", i);
    } else if (s.step_distance[i] > 0.005 && !border) {
      ++plane;
      plane_excluded += out.flag("excluded", i);
    }
  }
  std::printf("[ step plane, default ] at the step %zu of %zu excluded, plane %zu of %zu\n", at_step_excluded,
              at_step, plane_excluded, plane);
  EXPECT_TRUE(out.flag("excluded", s.flying)) << "the flying point";
  EXPECT_EQ(at_step_excluded, at_step) << "a window across a 3 mm step holds two layers";
  EXPECT_LE(plane_excluded, plane / 100) << "clean surface is kept";
}

TEST(Preselection, PaperRuleExcludesMuchOfTheSamePlane) {
  const StepPlane s = makeStepPlane();
  const PointCloud out = smoothedWith(s.cloud, PreselectionRule::PaperMean);
  std::size_t excluded = 0;
  for (std::size_t i = 0; i < out.size(); ++i) excluded += out.flag("excluded", i);
  EXPECT_TRUE(out.flag("excluded", s.flying));
  EXPECT_GE(excluded, out.size() / 4) << "two 'below the mean' tests";
}

TEST(Preselection, NoiseThatDoublesHalfwayIsNotAnEdge) {
  // sigma 0.25 mm for x < 75 mm, 0.5 mm beyond: both halves are surface.
  // The default rule keeps both; the paper's rule excludes most of the
  // noisier half, whose windows are less flat than the mean.
  PointCloud cloud;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<bool> noisy_half;
  for (int i = 0; i < 150; ++i)
    for (int j = 0; j < 150; ++j) {
      const double x = (i + 0.5) * kSpacing, y = (j + 0.5) * kSpacing;
      const double sigma = x < 0.075 ? 0.00025 : 0.0005;
      cloud.positions.emplace_back(x, y, sigma * gauss(rng));
      noisy_half.push_back(x >= 0.075);
    }
  const auto shares = [&](const PointCloud& out) {
    double counts[2] = {0, 0}, excluded[2] = {0, 0};
    for (std::size_t i = 0; i < out.size(); ++i) {
      counts[noisy_half[i]] += 1;
      excluded[noisy_half[i]] += out.flag("excluded", i);
    }
    return std::pair<double, double>{excluded[0] / counts[0], excluded[1] / counts[1]};
  };
  const auto robust = shares(smoothedWith(cloud, PreselectionRule::Robust));
  const auto paper = shares(smoothedWith(cloud, PreselectionRule::PaperMean));
  std::printf("[ noise doubling ] default: quiet half %.1f %%, noisy half %.1f %%; paper-mean: %.1f %%, %.1f %%\n",
              100 * robust.first, 100 * robust.second, 100 * paper.first, 100 * paper.second);
  EXPECT_LE(robust.first, 0.02);
  EXPECT_LE(robust.second, 0.02);
  EXPECT_GE(paper.second, 0.8);
}

TEST(Preselection, RuleNoneExcludesNothingButStillReportsTheStatistics) {
  const Preselection p = preselect({10, 20, 30, 1}, {5, 4, 3, 0}, withRule(PreselectionRule::None));
  EXPECT_EQ(p.summary.excluded, 0u);
  EXPECT_EQ(p.excluded, (std::vector<std::uint8_t>{0, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(p.summary.mean_cardinality, 15.25);
  // Per unit of surface: the isolated point (|W| = 1) stands for more area
  // than the other three together.
  EXPECT_DOUBLE_EQ(p.summary.median_cardinality, 1.0);
  // F = 0 is left out of the statistics; the others weigh 1 / |W|:
  // 0.033, 0.05, 0.1 for F = 3, 4, 5, so half the weight is reached at 5.
  EXPECT_NEAR(p.summary.median_flatness, 5.0, 1e-12);
}

TEST(Preselection, PaperRuleThresholdsAreTheMeans) {
  const Preselection p = preselect({10, 20, 30, 40}, {1, 2, 2.5, 6.5}, withRule(PreselectionRule::PaperMean));
  EXPECT_DOUBLE_EQ(p.summary.cardinality_threshold, 25.0);
  EXPECT_DOUBLE_EQ(p.summary.flatness_threshold, 3.0);
  EXPECT_EQ(p.excluded, (std::vector<std::uint8_t>{1, 1, 1, 0}));
  EXPECT_EQ(p.summary.excluded_both, 2u);
  EXPECT_EQ(p.summary.excluded_flatness_only, 1u);
}

TEST(Preselection, DefaultRuleThresholdsFollowTheMedianAndSpread) {
  // ln F is 1.0 +- 0.1 around e: the threshold is e^(1 - 3 x spread); the
  // cardinality threshold is the smaller of median/2 and median - 3 sigma,
  // but at least 6.
  std::vector<double> cardinality, flatness;
  for (int i = 0; i < 101; ++i) {
    cardinality.push_back(i < 51 ? 41 : 42);  // median 41, MAD 0.5 (the isolated point below included: 1)
    flatness.push_back(std::exp(1.0 + 0.1 * ((i % 2) ? 1 : -1)));
  }
  flatness[0] = std::exp(1.0);  // an odd count: the median itself
  cardinality.push_back(2);     // an isolated point
  flatness.push_back(std::exp(1.0));
  const Preselection p = preselect(cardinality, flatness);
  const double spread = 1.4826 * 0.1;
  EXPECT_NEAR(p.summary.log_flatness_spread, spread, 1e-9);
  EXPECT_NEAR(p.summary.flatness_threshold, std::exp(1.0 - 3 * spread), 1e-9);
  EXPECT_DOUBLE_EQ(p.summary.cardinality_threshold, 20.5);  // median 41 / 2 < 41 - 3 x 1.48 x MAD
  EXPECT_EQ(p.summary.excluded, 1u);
  EXPECT_EQ(p.excluded.back(), 1);

  // Explicit thresholds replace the rule's own.
  PreselectionParameters given;
  given.flatness_threshold = 100.0;
  EXPECT_EQ(preselect(cardinality, flatness, given).summary.excluded, cardinality.size());
}

TEST(Preselection, FlatnessStatisticsArePerUnitOfSurface) {
  // 900 points of a dense, quiet patch (|W| = 90, F = 8) and 110 of a
  // sparse, noisier one (|W| = 10, F = 4) covering a little more surface:
  // per sample the median would be 8 and the whole sparse patch would fall
  // below 8 e^(-3 x 0.05); per unit of surface the sparse patch is the
  // larger half.
  std::vector<double> cardinality(900, 90.0), flatness(900, 8.0);
  cardinality.insert(cardinality.end(), 110, 10.0);
  flatness.insert(flatness.end(), 110, 4.0);
  const Preselection p = preselect(cardinality, flatness);
  EXPECT_EQ(p.summary.median_flatness, 4.0);
  EXPECT_EQ(p.summary.excluded, 0u);
}

TEST(Preselection, AWindowOfFlatnessZeroIsAlwaysExcluded) {
  PreselectionParameters params;
  params.flatness_threshold = 0.0;
  const Preselection p = preselect({30, 30, 30}, {5, 0, 5}, params);
  EXPECT_EQ(p.excluded, (std::vector<std::uint8_t>{0, 1, 0}));
}

TEST(Preselection, ReappliedFromAttributesDecidesAsTheSmoothingDid) {
  const StepPlane s = makeStepPlane();
  PointCloud out = smoothedWith(s.cloud, PreselectionRule::Robust);
  const std::vector<double> flags = out.attributes.get("excluded").values;
  out.attributes.remove("excluded");
  applyPreselection(out.attributes, out.size(), PreselectionParameters{}, "cloud.ply");
  EXPECT_EQ(out.attributes.get("excluded").values, flags);
}

TEST(Preselection, BadInputIsAnInputError) {
  EXPECT_EQ(icrkit::test::expectInputError([] { parsePreselectionRule("median"); }).source(),
            "PreselectionParameters::rule");
  EXPECT_EQ(icrkit::test::expectInputError([] { parsePreselectionRule("median", "--preselection"); }).source(),
            "--preselection");
  EXPECT_EQ(parsePreselectionRule("default"), PreselectionRule::Robust);
  EXPECT_EQ(parsePreselectionRule("paper-mean"), PreselectionRule::PaperMean);
  EXPECT_EQ(parsePreselectionRule("none"), PreselectionRule::None);
  EXPECT_THROW(preselect({1, 2}, {1}), InputError);
  EXPECT_THROW(preselect({1, -2}, {1, 1}), InputError);
  EXPECT_THROW(preselect({1, 2}, {1, std::nan("")}), InputError);
  PreselectionParameters bad;
  bad.robust_k = -1;
  EXPECT_THROW(preselect({1, 2}, {1, 1}, bad), InputError);
  PreselectionParameters negative;
  negative.flatness_threshold = -1.0;
  EXPECT_EQ(icrkit::test::expectInputError([&] { negative.validate(); }).source(),
            "PreselectionParameters::flatness_threshold");
  negative = {};
  negative.cardinality_threshold = std::nan("");
  EXPECT_EQ(icrkit::test::expectInputError([&] {
              preselect({1, 2}, {1, 1}, negative);
            }).source(),
            "PreselectionParameters::cardinality_threshold");
  AttributeSet empty;
  try {
    applyPreselection(empty, 3, {}, "mesh.ply");
    FAIL() << "no attributes";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "mesh.ply");
    EXPECT_NE(e.detail().find("cardinality"), std::string::npos);
  }
}

TEST(PreselectionRecord, SaysWhatTheRuleDid) {
  PreselectionReport summary;
  summary.rule = PreselectionRule::PaperMean;
  summary.points = 200;
  summary.excluded = 50;
  summary.excluded_both = 10;
  summary.cardinality_threshold = 12.5;
  const std::string mean = preselectionRecordJson(summary, true, false);
  EXPECT_NE(mean.find("\"rule\":\"paper-mean\""), std::string::npos) << mean;
  EXPECT_NE(mean.find("\"cardinality_source\":\"given\""), std::string::npos) << mean;
  EXPECT_NE(mean.find("\"flatness_source\":\"mean\""), std::string::npos) << mean;
  EXPECT_NE(mean.find("\"percent\":25.0"), std::string::npos) << mean;
  summary.rule = PreselectionRule::None;
  const std::string none = preselectionRecordJson(summary);
  EXPECT_NE(none.find("\"excluded\":null"), std::string::npos) << none;
  EXPECT_NE(none.find("\"thresholds\":null"), std::string::npos) << none;
}

}  // namespace
}  // namespace icrkit::ndt
