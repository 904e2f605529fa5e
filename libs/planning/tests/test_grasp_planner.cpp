#include "planning_meshes.hpp"
#include "test_support.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/planning/grasp_planner.hpp>
#include <icrkit/planning/plan_file.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>

using namespace icrkit;
using namespace icrkit::planning;

namespace {

PlanningParameters cubeParameters() {
  PlanningParameters p;
  p.finger_counts = {4};
  p.top = 5;
  p.candidates = 300;
  p.regions.tws_radius = 0.05;
  p.placement.placement_error_m = 0.002;
  return p;
}

bool holds(const icr::GraspableObject& object, const std::vector<int>& contacts, const icr::ContactModel& model,
           double radius) {
  const icr::GraspWrenchSpace gws = icr::graspWrenchSpace(object, contacts, model);
  return gws.force_closure && gws.epsilon >= radius;
}

}  // namespace

TEST(GraspPlanner, PlansRankedGraspsOnTrustedVerticesThatHoldTheTask) {
  const TriangleMesh cube = test::griddedCube(0.04, 20);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  const PlanningParameters params = cubeParameters();
  const PlanResult plan = planGrasps(object, params);
  ASSERT_EQ(plan.grasps.size(), 5u);
  const ContactTrust trust = assessContactTrust(cube, {}, params.trust);
  for (std::size_t g = 0; g < plan.grasps.size(); ++g) {
    const PlannedGrasp& grasp = plan.grasps[g];
    EXPECT_EQ(grasp.rank, g + 1);
    if (g > 0) EXPECT_LE(grasp.score.probability, plan.grasps[g - 1].score.probability);
    EXPECT_DOUBLE_EQ(grasp.tws_radius, 0.05);
    EXPECT_DOUBLE_EQ(grasp.growth_tws_radius, 0.05 * 1.25);
    EXPECT_GE(grasp.epsilon, grasp.growth_tws_radius);
    std::vector<int> aims;
    for (const icr::ContactRegion& r : grasp.regions.regions) {
      ASSERT_FALSE(r.vertices.empty());
      for (int v : r.vertices) EXPECT_EQ(trust.untrusted[static_cast<std::size_t>(v)], 0) << "vertex " << v;
      aims.push_back(r.recommended.vertex);
    }
    // The ICR guarantee: one vertex per region, here the aims, holds the grown task.
    EXPECT_TRUE(holds(object, aims, params.regions.contact_model, grasp.growth_tws_radius));
  }
  // On a 4 cm cube with 2 mm placement error the best grasps sit on face centres.
  EXPECT_GT(plan.grasps.front().score.probability, 0.9);
}

TEST(GraspPlanner, SamePlanForAnyThreadCount) {
  const TriangleMesh cube = test::griddedCube(0.04, 16);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  const auto planWith = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    return planJson("cube.ply", object, cubeParameters().regions.contact_model, planGrasps(object, cubeParameters()));
  };
  EXPECT_EQ(planWith(1), planWith(2));
}

TEST(GraspPlanner, PlacementErrorZeroGivesCertainLanding) {
  const TriangleMesh cube = test::griddedCube(0.04, 16);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  PlanningParameters params = cubeParameters();
  params.placement.placement_error_m = 0.0;
  for (const PlannedGrasp& g : planGrasps(object, params).grasps) EXPECT_DOUBLE_EQ(g.score.probability, 1.0);
}

TEST(GraspPlanner, PatchFingersGetRegionsWhosePatchAimsHoldTheTask) {
  const TriangleMesh cube = test::griddedCube(0.04, 20);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  PlanningParameters params = cubeParameters();
  params.patch = icr::PatchParameters{};
  params.patch->radius_m = 0.003;
  const PlanResult plan = planGrasps(object, params);
  ASSERT_EQ(plan.grasps.size(), 5u);
  ASSERT_TRUE(plan.patch.has_value());
  const ContactTrust trust = assessContactTrust(cube, {}, params.trust);
  const icr::GraspableObject trusted(cube, object.frame(), trust.untrusted);
  const icr::ContactPatches patches(trusted, *params.patch);
  for (std::size_t g = 0; g < plan.grasps.size(); ++g) {
    const PlannedGrasp& grasp = plan.grasps[g];
    if (g > 0) EXPECT_LE(grasp.score.probability, plan.grasps[g - 1].score.probability);
    std::vector<int> aims;
    for (const icr::ContactRegion& r : grasp.regions.regions) {
      for (int v : r.vertices) EXPECT_EQ(trust.untrusted[static_cast<std::size_t>(v)], 0) << "vertex " << v;
      aims.push_back(r.recommended.vertex);
    }
    // The ICR guarantee of the patch model: patch fingers at the aims hold the grown task.
    const icr::GraspWrenchSpace gws = icr::patchGraspWrenchSpace(patches, aims, params.regions.contact_model);
    EXPECT_TRUE(gws.force_closure);
    EXPECT_GE(gws.epsilon, grasp.growth_tws_radius);
  }
  EXPECT_NE(planJson("cube", object, params.regions.contact_model, plan).find("\"patch\":{\"filter_border\":true,\"radius_m\":0.003}"),
            std::string::npos);
  params.regions.conservative = icr::ConservativeGrowth{};
  EXPECT_EQ(test::expectInputError([&] { planGrasps(object, params); }).source(), "PlanningParameters::patch");
}

TEST(GraspPlanner, RefusesWhatCannotBePlanned) {
  const TriangleMesh cube = test::griddedCube(0.04, 10);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  PlanningParameters params = cubeParameters();
  params.top = 0;
  EXPECT_EQ(test::expectInputError([&] { planGrasps(object, params); }).source(), "PlanningParameters::top");
  params = cubeParameters();
  params.regions.tws_radius = 10.0;  // far beyond any grasp's epsilon
  const InputError task = test::expectInputError([&] { planGrasps(object, params); });
  EXPECT_NE(std::string(task.what()).find("no candidate meets the task"), std::string::npos) << task.what();
  params = cubeParameters();
  params.regions.contact_model.type = icr::ContactType::Frictionless;
  params.finger_counts = {2};
  const InputError closure = test::expectInputError([&] { planGrasps(object, params); });
  EXPECT_NE(std::string(closure.what()).find("no force-closure grasp among 300 candidates"), std::string::npos)
      << closure.what();
  const icr::GraspableObject excluded = icr::GraspableObject::withDefaultFrame(
      cube, std::vector<std::uint8_t>(cube.vertexCount(), 1), icr::TorqueReference::Centroid);
  const InputError none = test::expectInputError([&] { planGrasps(excluded, cubeParameters()); });
  EXPECT_NE(std::string(none.what()).find("trusted vertices"), std::string::npos) << none.what();
}

TEST(PlanFile, RoundTripsAndNamesBadElements) {
  const TriangleMesh cube = test::griddedCube(0.04, 16);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(cube, {}, icr::TorqueReference::Centroid);
  const PlanResult plan = planGrasps(object, cubeParameters());
  const std::string text = planJson("cube.ply", object, cubeParameters().regions.contact_model, plan);
  const StoredPlan stored = parsePlanJson(text, "plan.json", cube.vertexCount());
  EXPECT_EQ(stored.mesh, "cube.ply");
  EXPECT_NEAR(stored.frame.lambda, object.frame().lambda, 1e-15);
  ASSERT_EQ(stored.grasps.size(), plan.grasps.size());
  for (std::size_t g = 0; g < plan.grasps.size(); ++g)
    for (std::size_t n = 0; n < 4; ++n) {
      EXPECT_EQ(stored.grasps[g].regions[n].vertices, plan.grasps[g].regions.regions[n].vertices);
      EXPECT_EQ(stored.grasps[g].regions[n].recommended, plan.grasps[g].regions.regions[n].recommended.vertex);
    }
  const InputError range = test::expectInputError([&] { parsePlanJson(text, "plan.json", 10); });
  EXPECT_EQ(range.source(), "plan.json");
  EXPECT_EQ(range.location().rfind("grasps[0].regions[0]", 0), 0u) << range.location();
  const InputError broken = test::expectInputError([&] { parsePlanJson("{\"mesh\": 3}", "p.json"); });
  EXPECT_EQ(broken.location(), "mesh");
  EXPECT_NO_THROW(parsePlanJson(text, "plan.json"));
}

TEST(GraspPlanner, RealScannedObjectOfTheAuthorsLibrary) {
  const std::string path = test::sharedData("icr-models/Tortoise_5k.obj");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "SKIPPED: shared data not found: " << path;
  const TriangleMesh mesh = io::readTriangleMesh(path);
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(mesh, {}, icr::TorqueReference::Centroid);
  PlanningParameters params;
  params.candidates = 500;
  params.top = 5;
  params.regions.alpha = 0.5;
  const PlanResult plan = planGrasps(object, params);
  ASSERT_EQ(plan.grasps.size(), 5u);
  for (const PlannedGrasp& g : plan.grasps) {
    std::vector<int> aims;
    for (const icr::ContactRegion& r : g.regions.regions) aims.push_back(r.recommended.vertex);
    EXPECT_TRUE(holds(object, aims, params.regions.contact_model, g.growth_tws_radius));
    EXPECT_GT(g.score.probability, 0.0);
  }
}
