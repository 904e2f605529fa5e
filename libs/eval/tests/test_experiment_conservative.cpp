// The experiment with conservative growth beside plain growth, and where the
// recommended contacts land (ExperimentConfig::conservative_sigmas,
// conservative_summary.hpp).

#include <icrkit/core/error.hpp>
#include <icrkit/eval/conservative_summary.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/report/conservative_plot.hpp>

#include "experiment_test_support.hpp"

#include <gtest/gtest.h>

namespace icrkit::eval {
namespace {

void addSigmas(TriangleMesh& mesh, double normal_sigma, double position_sigma) {
  mesh.vertices.attributes.add("normal_sigma", ScalarType::Float32, mesh.vertexCount(), normal_sigma);
  mesh.vertices.attributes.add("position_sigma", ScalarType::Float32, mesh.vertexCount(), position_sigma);
}

TEST(ExperimentConservative, KZeroRepeatsThePlainRegionsAndLargerKShrinksThem) {
  const TriangleMesh cad = test::ellipsoid(4);
  TriangleMesh raw = test::noisyCopy(cad, 5e-4, 3);
  TriangleMesh filtered = test::noisyCopy(cad, 2e-4, 4);
  addSigmas(raw, 0.03, 5e-4);
  addSigmas(filtered, 0.01, 2e-4);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 8;
  config.conservative_sigmas = {0.0, 1.0, 3.0};
  const DatasetExperiment experiment({"ellipsoid", &cad, &raw, &filtered}, config);
  const std::vector<GraspRecord> records = experiment.run(0, experiment.itemCount());
  std::size_t evaluated = 0, shrunk = 0;
  for (const GraspRecord& r : records) {
    if (!r.evaluated) {
      EXPECT_TRUE(r.filtered.conservative.empty());
      continue;
    }
    ++evaluated;
    for (const MeshOutcome* m : {&r.raw, &r.filtered}) {
      ASSERT_EQ(m->conservative.size(), 3u);
      for (std::size_t n = 0; n < m->regions.size(); ++n) {
        ASSERT_TRUE(m->regions[n].recommended_inside.has_value());
        // K = 0 repeats the plain comparison.
        EXPECT_EQ(m->conservative[0].regions[n].vertices, m->regions[n].vertices);
        EXPECT_EQ(m->conservative[0].regions[n].intersection_area_m2, m->regions[n].intersection_area_m2);
        EXPECT_EQ(m->conservative[0].regions[n].recommended_inside, m->regions[n].recommended_inside);
        EXPECT_LE(m->conservative[1].regions[n].vertices, m->regions[n].vertices);
        EXPECT_LE(m->conservative[2].regions[n].vertices, m->conservative[1].regions[n].vertices);
        EXPECT_LE(m->conservative[2].regions[n].false_positive_area_m2,
                  m->conservative[1].regions[n].false_positive_area_m2 + 1e-15);
        if (m->conservative[2].regions[n].vertices < m->regions[n].vertices) ++shrunk;
      }
    }
    for (const MeshOutcome* m : {&r.raw, &r.filtered}) {
      ASSERT_TRUE(m->picks.has_value());
      EXPECT_EQ(m->picks->tried, config.picks_per_grasp);
      EXPECT_LE(m->picks->held, m->picks->mapped);
      EXPECT_LE(m->picks->mapped, m->picks->tried);
      // Drawn picks come with the aimed grasp's verdict.
      EXPECT_EQ(m->picks->aimed_held.has_value(), m->picks->tried > 0);
      for (const ConservativeOutcome& c : m->conservative) ASSERT_TRUE(c.picks.has_value());
    }
    // The records round-trip with the new fields.
    EXPECT_EQ(toJsonLine(fromJsonLine(toJsonLine(r))), toJsonLine(r));
  }
  EXPECT_GT(evaluated, 3u);
  EXPECT_GT(shrunk, 0u);

  const ConservativeSummary summary = computeConservativeSummary(records);
  EXPECT_EQ(summary.sigmas, (std::vector<double>{0.0, 1.0, 3.0}));
  ASSERT_EQ(summary.rows.size(), 8u);  // (ellipsoid, All) x (plain, 0, 1, 3)
  const GrowthRow& plain = summary.rows[4];
  const GrowthRow& k0 = summary.rows[5];
  EXPECT_EQ(plain.dataset, "All");
  EXPECT_FALSE(plain.sigmas.has_value());
  EXPECT_EQ(k0.filtered.intersection_percent, plain.filtered.intersection_percent);
  EXPECT_EQ(k0.filtered.recommended_inside, plain.filtered.recommended_inside);
  EXPECT_EQ(plain.filtered.recommended_known, plain.filtered.regions);
  // The near-perfect filtered mesh puts its recommended contacts inside.
  EXPECT_GT(*plain.filtered.recommendedInsidePercent(), 80.0);
  // Picks from regions of a near-perfect reconstruction hold on the CAD mesh.
  EXPECT_GT(plain.filtered.picks_mapped, 0u);
  EXPECT_GT(*plain.filtered.picksHeldPercent(), 80.0);
  EXPECT_GT(plain.filtered.aimed_known, 0u);
  EXPECT_GT(*plain.filtered.aimedHeldPercent(), 80.0);
  EXPECT_NE(report::conservativeCurveSvg(summary).find("<polyline"), std::string::npos);
  EXPECT_NE(report::conservativeSummaryMarkdown(summary).find("| All | K 3 |"), std::string::npos);
}

// On the CAD mesh itself every region is the CAD region: by the ICR
// theorem any pick holds, the recommended contacts' grasp among them.
TEST(ExperimentConservative, TheAimedGraspOnThePerfectReconstructionAlwaysHolds) {
  const TriangleMesh cad = test::ellipsoid(4);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 8;
  const DatasetExperiment experiment({"perfect", &cad, &cad, &cad}, config);
  std::size_t aimed = 0;
  for (const GraspRecord& r : experiment.run(0, experiment.itemCount())) {
    if (!r.evaluated) continue;
    for (const MeshOutcome* m : {&r.raw, &r.filtered}) {
      ASSERT_TRUE(m->picks.has_value());
      EXPECT_EQ(m->picks->held, m->picks->mapped);
      if (!m->picks->aimed_held) continue;
      EXPECT_TRUE(*m->picks->aimed_held) << r.index;
      ++aimed;
    }
  }
  EXPECT_GT(aimed, 4u);
}

TEST(ExperimentConservative, MeshesWithoutSigmasAreRefusedClearly) {
  const TriangleMesh cad = test::ellipsoid(3);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 4;
  config.conservative_sigmas = {1.0};
  const DatasetExperiment experiment({"bare", &cad, &cad, &cad}, config);
  EXPECT_THROW(experiment.run(0, experiment.itemCount()), InputError);
  config.conservative_sigmas = {-1.0};
  EXPECT_THROW(DatasetExperiment({"bad", &cad, &cad, &cad}, config), InputError);
}

}  // namespace
}  // namespace icrkit::eval
