// The planned grasps executed on the CAD mesh (planned_grasps.hpp).

#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/planned_grasps.hpp>

#include "experiment_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace icrkit::eval {
namespace {

using test::ellipsoid;

ExperimentConfig fourFingers(std::size_t grasps) {
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = grasps;
  return config;
}

planning::PlanningParameters smallPlan() {
  planning::PlanningParameters p;
  p.top = 3;
  p.candidates = 200;
  return p;
}

TEST(PlannedGrasps, OnTheCadMeshItselfEveryAimedGraspAndPickHolds) {
  // Reconstruction = CAD: every contact maps onto itself, so the ICR
  // guarantee (regions grown for the task with its margin) must hold for the
  // aimed grasp and for every pick.
  const TriangleMesh mesh = ellipsoid(4);
  const DatasetExperiment experiment({"same", &mesh, &mesh, &mesh}, fourFingers(20));
  PlannedExecutionParameters execution;
  execution.picks_per_grasp = 30;
  execution.placement_samples = 30;
  const PlannedGraspStudy study = experiment.plannedGrasps(smallPlan(), execution);
  EXPECT_EQ(study.fingers, 4u);
  EXPECT_EQ(study.cad_grasps, 20u);
  EXPECT_GT(study.tws_radius, 0.0);
  for (const PlannedMeshStudy* s : {&study.raw, &study.filtered}) {
    ASSERT_TRUE(s->error.empty()) << s->error;
    ASSERT_EQ(s->grasps.size(), 3u);
    for (const PlannedGraspExecution& g : s->grasps) {
      EXPECT_TRUE(g.aimed_held) << s->mesh << " rank " << g.rank;
      EXPECT_GE(g.aimed_epsilon, study.tws_radius);
      EXPECT_EQ(g.picks, 30u);
      EXPECT_EQ(g.picks_held, 30u) << s->mesh << " rank " << g.rank;
      EXPECT_EQ(g.unmapped, 0u);
      EXPECT_LE(g.placements_held, g.placements);
    }
    EXPECT_DOUBLE_EQ(s->aimedHeldFraction(), 1.0);
    EXPECT_GT(s->medianRegionAreaM2(), 0.0);
  }
  // The baseline: random grasps meeting the same task, kept in draw order.
  ASSERT_TRUE(study.filtered_random.error.empty());
  EXPECT_EQ(study.filtered_random.grasps.size(), 3u);
  for (std::size_t k = 0; k < study.filtered_random.grasps.size(); ++k)
    EXPECT_EQ(study.filtered_random.grasps[k].rank, k + 1);

  // Deterministic (planned.jsonl holds no timings), and one line of
  // planned.jsonl that the table reads.
  EXPECT_EQ(plannedGraspStudyJson(experiment.plannedGrasps(smallPlan(), execution)), plannedGraspStudyJson(study));
  const nlohmann::json line = nlohmann::json::parse(plannedGraspStudyJson(study));
  EXPECT_EQ(line.at("dataset"), "same");
  EXPECT_EQ(line.at("filtered").at("grasps").size(), 3u);
  const std::string table = plannedGraspStudiesMarkdown({plannedGraspStudyJson(study)});
  EXPECT_NE(table.find("| same | filtered | "), std::string::npos);
  EXPECT_NE(table.find("| 100.0 | 100.0 |"), std::string::npos);
}

TEST(PlannedGrasps, AMeshWithoutTrustedSurfaceIsReportedNotThrown) {
  // A reconstruction far from the CAD (5 cm off) still plans, but nothing
  // maps: every trial fails, none crashes.
  const TriangleMesh cad = ellipsoid(4);
  TriangleMesh far = cad;
  for (auto& p : far.vertices.positions) p.x() += 0.05;
  const DatasetExperiment experiment({"far", &cad, &far, &far}, fourFingers(10));
  PlannedExecutionParameters execution;
  execution.picks_per_grasp = 5;
  execution.placement_samples = 5;
  const PlannedGraspStudy study = experiment.plannedGrasps(smallPlan(), execution);
  ASSERT_TRUE(study.filtered.error.empty()) << study.filtered.error;
  for (const PlannedGraspExecution& g : study.filtered.grasps) {
    EXPECT_FALSE(g.aimed_held);
    EXPECT_EQ(g.picks_held, 0u);
    EXPECT_EQ(g.unmapped, g.picks + g.placements);
  }
}

}  // namespace
}  // namespace icrkit::eval
