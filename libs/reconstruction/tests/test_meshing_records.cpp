// Ball pivoting's parameter checks and record (ball_pivoting_record.hpp),
// and the raw mesh with one filtered mesh per preselection rule
// (meshes_per_rule.hpp) on a known surface: an icosphere's vertices.

#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting_record.hpp>
#include <icrkit/reconstruction/meshing/meshes_per_rule.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <limits>

namespace icrkit::reconstruction {
namespace {

PointCloud sphereVertices() {
  const TriangleMesh sphere = makeIcosphere(3, 0.05);
  PointCloud cloud;
  cloud.positions = sphere.vertices.positions;
  for (const auto& p : cloud.positions) cloud.normals.push_back(p.normalized());
  return cloud;
}

TEST(BallPivotingParameters, EachFieldIsNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NO_THROW(BallPivotingParameters{}.validate());
  BallPivotingParameters p;
  p.radii = {};
  EXPECT_EQ(test::expectInputError([&] { p.validate(); }).source(), "BallPivotingParameters::radii");
  p = {};
  p.radii = {Length::spacings(1.5), Length::metres(-0.001)};
  EXPECT_EQ(test::expectInputError([&] { p.validate(); }).source(), "BallPivotingParameters::radii");
  p = {};
  p.duplicate_distance = -1.0;
  EXPECT_EQ(test::expectInputError([&] { p.validate(); }).source(), "BallPivotingParameters::duplicate_distance");
  p = {};
  p.thinning_factor = nan;
  EXPECT_EQ(test::expectInputError([&] { p.validate(); }).source(), "BallPivotingParameters::thinning_factor");
  // ballPivoting() checks them before any work.
  EXPECT_EQ(test::expectInputError([&] { ballPivoting(sphereVertices(), p); }).source(),
            "BallPivotingParameters::thinning_factor");
}

TEST(BallPivotingParameters, RadiiInMetresAndSpacingsMix) {
  const PointCloud cloud = sphereVertices();
  BallPivotingParameters p;
  p.radii = {Length::metres(0.02), Length::spacings(2.0)};
  const std::vector<double> radii = ballPivotingRadii(cloud, p);
  ASSERT_EQ(radii.size(), 2u) << "no gap radius: not every radius is relative";
  const BallPivotingResult plain = ballPivoting(cloud, BallPivotingParameters{});
  EXPECT_NEAR(radii[0], 2.0 * plain.report.median_spacing, 1e-12);
  EXPECT_DOUBLE_EQ(radii[1], 0.02);
}

TEST(BallPivotingRecord, HoldsTheReport) {
  const BallPivotingResult result = ballPivoting(sphereVertices());
  const nlohmann::json record = nlohmann::json::parse(ballPivotingRecordJson(result.report));
  EXPECT_EQ(record["triangles"], result.report.triangles);
  EXPECT_EQ(record["points"], result.report.points);
  EXPECT_EQ(record["passes"].size(), result.report.passes.size());
  EXPECT_EQ(record["radii_m"][0], result.report.passes[0].radius);
  EXPECT_EQ(record["boundary_loops"], 0u) << "a closed sphere";
  EXPECT_EQ(record["euler_characteristic"], 2);
}

TEST(MeshesPerRule, OneFilteredMeshPerRule) {
  PointCloud cloud = sphereVertices();
  const std::vector<ndt::PreselectionRule> rules{ndt::PreselectionRule::Robust, ndt::PreselectionRule::None};
  RawAndFilteredParameters params;
  const MeshesPerRule meshes = meshRawAndFilteredPerRule(cloud, rules, params);
  ASSERT_EQ(meshes.filtered.size(), 2u);
  EXPECT_GT(meshes.raw.faceCount(), 0u);
  EXPECT_EQ(meshes.filtered[0].faces, meshes.filtered[1].faces) << "one smoothing, only the flags differ";
  ASSERT_TRUE(meshes.filtered[1].vertices.attributes.has("excluded"));
  for (double flag : meshes.filtered[1].vertices.attributes.get("excluded").values)
    EXPECT_EQ(flag, 0.0) << "rule none excludes nothing";
  params.mesh_kept_points_only = true;
  const MeshesPerRule kept = meshRawAndFilteredPerRule(cloud, rules, params);
  ASSERT_EQ(kept.filtered.size(), 2u);
  EXPECT_EQ(kept.raw.faces, meshes.raw.faces);
}

}  // namespace
}  // namespace icrkit::reconstruction
