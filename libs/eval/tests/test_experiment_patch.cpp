// The experiment's patch-contact study (ExperimentConfig::patch): every
// evaluated grasp run again with the reference library's multi-point
// contacts on all three meshes, against its own task and CAD regions.

#include <icrkit/core/error.hpp>
#include <icrkit/eval/conservative_summary.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/report/conservative_plot.hpp>

#include "experiment_test_support.hpp"

#include <gtest/gtest.h>

namespace icrkit::eval {
namespace {

// An icosphere of 3 subdivisions has edges of about 5 mm: 6 mm patches reach
// the one-ring, so every patch has a border and the hulls stay small.
ExperimentConfig patchConfig() {
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 6;
  config.patch = icr::PatchParameters{};
  config.patch->radius_m = 0.006;
  return config;
}

// On the CAD mesh itself the patch regions are the CAD patch regions, and
// by the ICR theorem (which holds for patch contacts as for points) the
// grasp of the recommended contacts holds the patch task.
TEST(ExperimentPatch, OnThePerfectReconstructionThePatchRegionsAreTheCadOnes) {
  const TriangleMesh cad = test::ellipsoid(3);
  const ExperimentConfig config = patchConfig();
  const DatasetExperiment experiment({"perfect", &cad, &cad, &cad}, config);
  const std::vector<GraspRecord> records = experiment.run(0, experiment.itemCount());
  std::size_t studied = 0, areas_compared = 0;
  for (const GraspRecord& r : records) {
    if (!r.evaluated) {
      EXPECT_FALSE(r.patch.has_value());
      continue;
    }
    ASSERT_TRUE(r.patch.has_value());
    const PatchRecord& p = *r.patch;
    EXPECT_EQ(p.radius_m, 0.006);
    // Every patch holds its centre: the patch GWS holds the point GWS.
    EXPECT_GE(p.cad_epsilon, r.cad_epsilon - 1e-12);
    EXPECT_DOUBLE_EQ(p.tws_radius, config.alpha * p.cad_epsilon);
    ASSERT_TRUE(p.evaluated) << p.raw.reason;
    ++studied;
    ASSERT_EQ(p.cad_region_areas_m2.size(), r.fingers);
    for (const PatchMeshOutcome* m : {&p.raw, &p.filtered}) {
      EXPECT_TRUE(m->task_fulfilled);
      EXPECT_DOUBLE_EQ(m->epsilon, p.cad_epsilon);
      ASSERT_EQ(m->regions.size(), r.fingers);
      for (std::size_t n = 0; n < r.fingers; ++n) {
        EXPECT_EQ(m->regions[n].recommended_inside, std::optional<bool>(true));
        // A region of one or two vertices has no area to compare.
        if (p.cad_region_areas_m2[n] == 0.0) continue;
        ++areas_compared;
        EXPECT_NEAR(*m->regions[n].intersection_percent, 100.0, 1e-6);
        EXPECT_NEAR(*m->regions[n].false_positive_percent, 0.0, 1e-6);
      }
      EXPECT_EQ(m->aimed_held, std::optional<bool>(true));
    }
    EXPECT_EQ(toJsonLine(fromJsonLine(toJsonLine(r))), toJsonLine(r));
  }
  EXPECT_GT(studied, 2u);
  EXPECT_GT(areas_compared, 4u);

  const ConservativeSummary summary = computeConservativeSummary(records);
  EXPECT_EQ(summary.patch_radii_m, (std::vector<double>{0.006}));
  ASSERT_EQ(summary.rows.size(), 4u);  // (perfect, All) x (plain, patch)
  const GrowthRow& patch = summary.rows[3];
  EXPECT_EQ(patch.dataset, "All");
  EXPECT_EQ(patch.patch_radius_m, std::optional<double>(0.006));
  EXPECT_FALSE(patch.sigmas.has_value());
  EXPECT_EQ(patch.evaluated_grasps, studied);
  EXPECT_EQ(patch.studied_grasps, studied);  // the perfect mesh meets every patch task
  EXPECT_EQ(patch.filtered_task_met, studied);
  EXPECT_EQ(summary.rows[2].studied_grasps, 0u);  // All, plain: not a patch row
  EXPECT_EQ(patch.filtered.aimed_known, studied);
  EXPECT_EQ(patch.filtered.aimed_held, studied);
  EXPECT_EQ(patch.filtered.grasps_with_picks, 0u);
  EXPECT_NE(report::conservativeSummaryMarkdown(summary).find("| All | patch 6 mm |"), std::string::npos);
  const std::string json = conservativeSummaryJson(summary);
  EXPECT_NE(json.find("\"growth\": \"patch\""), std::string::npos);
  EXPECT_NE(json.find("\"patch_radius_m\": 0.006"), std::string::npos);
  EXPECT_NE(json.find("\"patch_radii_m\""), std::string::npos);
  EXPECT_NE(json.find("\"studied_grasps\""), std::string::npos);
  EXPECT_NE(report::conservativeCurveSvg(summary).find("patch 6 mm"), std::string::npos);
}

// The study sits beside the paper's experiment: with it or without it the
// plain records are the same, bit for bit.
TEST(ExperimentPatch, ThePlainOutcomeDoesNotChange) {
  const TriangleMesh cad = test::ellipsoid(3);
  const TriangleMesh raw = test::noisyCopy(cad, 5e-4, 3);
  const TriangleMesh filtered = test::noisyCopy(cad, 2e-4, 4);
  ExperimentConfig config = patchConfig();
  const DatasetExperiment with_patch({"ellipsoid", &cad, &raw, &filtered}, config);
  std::vector<GraspRecord> records = with_patch.run(0, with_patch.itemCount());
  std::size_t studied = 0, evaluated = 0;
  for (GraspRecord& r : records) {
    EXPECT_EQ(r.patch.has_value(), r.evaluated);
    if (r.patch && r.patch->evaluated) {
      ++studied;
      for (const PatchMeshOutcome* m : {&r.patch->raw, &r.patch->filtered}) {
        EXPECT_GE(m->epsilon, r.patch->tws_radius);
        for (const RegionComparison& region : m->regions) EXPECT_GT(region.vertices, 0u);  // the contact is always in
        EXPECT_TRUE(m->aimed_held.has_value());
      }
    }
    evaluated += r.evaluated;
    r.patch.reset();
  }
  EXPECT_GT(studied, 0u);
  config.patch.reset();
  const DatasetExperiment without({"ellipsoid", &cad, &raw, &filtered}, config);
  EXPECT_EQ(test::recordLines(records), test::recordLines(without.run(0, without.itemCount())));
  EXPECT_GT(evaluated, 2u);
}

TEST(ExperimentPatch, ARadiusThatIsNotPositiveIsRefused) {
  const TriangleMesh cad = test::ellipsoid(2);
  for (const double radius : {0.0, -0.001, std::numeric_limits<double>::infinity()}) {
    ExperimentConfig config = patchConfig();
    config.patch->radius_m = radius;
    EXPECT_THROW(DatasetExperiment({"bad", &cad, &cad, &cad}, config), InputError) << radius;
  }
}

}  // namespace
}  // namespace icrkit::eval
