// The sensitivity study's own logic (sampling, noise, sharding, the table)
// with builders whose meshes have known answers; the meshing itself is the
// reconstruction library's and is tested there and in tests/cli_sensitivity.sh.

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/sensitivity_study.hpp>
#include <icrkit/report/sensitivity_plot.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace icrkit::eval {
namespace {

TriangleMesh ellipsoid() {
  TriangleMesh mesh = makeIcosphere(4, 0.04);
  for (auto& p : mesh.vertices.positions) p = p.cwiseProduct(Eigen::Vector3d(1.4, 1.0, 0.8));
  computeVertexNormals(mesh);
  return mesh;
}

SensitivityParameters smallStudy() {
  SensitivityParameters params;
  params.spacing_m = 0.004;
  params.noise_levels = {0.0, 0.5};
  params.rules = {"default", "none"};
  params.experiment.finger_counts = {4};
  params.experiment.grasps_per_set = 6;
  return params;
}

// A perfect reconstruction: the CAD mesh itself, raw and filtered alike.
SensitivityMeshBuilder perfect(const TriangleMesh& cad, const std::vector<std::string>& rules) {
  return [&cad, rules](const PointCloud&, double, double) {
    SensitivityMeshes m;
    m.raw = cad;
    for (const std::string& rule : rules) m.filtered.push_back({rule, cad, rule != "none"});
    return m;
  };
}

TEST(SensitivityStudy, NoiseIsGaussianAlongTheNormalsAndSeeded) {
  const TriangleMesh cad = ellipsoid();
  const SensitivityParameters params = smallStudy();
  const PointCloud sample = sensitivitySample(cad, params);
  ASSERT_GT(sample.size(), 500u);
  const PointCloud noisy = addNormalNoise(sample, 0.001, 42);
  double sum2 = 0, tangential = 0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const Eigen::Vector3d d = noisy.positions[i] - sample.positions[i];
    const double along = d.dot(sample.normals[i]);
    sum2 += along * along;
    tangential = std::max(tangential, (d - along * sample.normals[i]).norm());
  }
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(sample.size())), 0.001, 0.0001);
  EXPECT_LT(tangential, 1e-15);
  EXPECT_EQ(addNormalNoise(sample, 0.001, 42).positions, noisy.positions);
  EXPECT_EQ(addNormalNoise(sample, 0.0, 42).positions, sample.positions);
}

TEST(SensitivityStudy, APerfectReconstructionGivesTheWholeRegionAndEqualFalsePositives) {
  // The zero-noise row's known answer: on the CAD mesh itself, raw and
  // filtered are the same mesh, so Int is 100 % and FP the same (0) for both.
  const TriangleMesh cad = ellipsoid();
  const SensitivityParameters params = smallStudy();
  const SensitivityResult result = runSensitivityStudy(cad, "ellipsoid", params, perfect(cad, params.rules));
  ASSERT_EQ(result.records.size(), sensitivityItems(params));
  const SensitivityTable table =
      computeSensitivityTable(result.records, "ellipsoid", result.spacing_m, params.noise_levels, params.rules);
  ASSERT_EQ(table.rows.size(), 4u);
  for (const SensitivityRow& row : table.rows) {
    EXPECT_EQ(row.grasps, 6u);
    ASSERT_TRUE(row.filtered_intersection_percent && row.raw_intersection_percent) << row.rule;
    EXPECT_NEAR(*row.raw_intersection_percent, 100.0, 1e-6);
    EXPECT_NEAR(*row.filtered_intersection_percent, 100.0, 1e-6);
    EXPECT_EQ(*row.raw_false_positive_percent, *row.filtered_false_positive_percent);
    EXPECT_NEAR(*row.raw_false_positive_percent, 0.0, 1e-6);
    EXPECT_EQ(*row.raw_eligible_percent, *row.filtered_eligible_percent);
  }
  EXPECT_EQ(table.rows[0].rule, "default");
  EXPECT_EQ(table.rows[3].noise_level, 0.5);
  EXPECT_NE(report::sensitivityMarkdown(table).find("| 0.50 | 2.000 | none |"), std::string::npos);
  EXPECT_NE(report::sensitivitySvg(table).find("<polyline"), std::string::npos);
  EXPECT_GT(report::sensitivityPng(table).size(), 1000u);
}

TEST(SensitivityStudy, ShardsCoverTheStudyOnceAndBuildOnlyTheirLevels) {
  const TriangleMesh cad = ellipsoid();
  const SensitivityParameters params = smallStudy();
  const auto whole = runSensitivityStudy(cad, "e", params, perfect(cad, params.rules)).records;
  std::vector<GraspRecord> parts;
  std::size_t builds = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto part = runSensitivityStudy(cad, "e", params, perfect(cad, params.rules), Shard{i, 3});
    for (const SensitivityLevelReport& level : part.levels) builds += level.built;
    parts.insert(parts.end(), part.records.begin(), part.records.end());
  }
  std::sort(parts.begin(), parts.end());
  ASSERT_EQ(parts.size(), whole.size());
  for (std::size_t i = 0; i < parts.size(); ++i) EXPECT_EQ(toJsonLine(parts[i]), toJsonLine(whole[i]));
  // 24 items in thirds of 8: levels hold items 0-11 and 12-23, so the
  // middle shard builds both and the others one each.
  EXPECT_EQ(builds, 4u);
}

TEST(SensitivityStudy, RulesExcludingContactsLowerTheFilteredEligibilityOnly) {
  // Every vertex excluded under "default": no filtered grasp is eligible,
  // the raw mesh is unaffected, and "none" ignores the flags.
  const TriangleMesh cad = ellipsoid();
  SensitivityParameters params = smallStudy();
  params.noise_levels = {0.0};
  const SensitivityResult result =
      runSensitivityStudy(cad, "e", params, [&](const PointCloud&, double, double) {
        SensitivityMeshes m;
        m.raw = cad;
        TriangleMesh flagged = cad;
        flagged.vertices.attributes.add("excluded", ScalarType::UInt8, cad.vertexCount(), 1.0);
        m.filtered.push_back({"default", flagged, true});
        m.filtered.push_back({"none", flagged, false});
        return m;
      });
  const SensitivityTable table = computeSensitivityTable(result.records, "e", result.spacing_m, {0.0}, params.rules);
  EXPECT_EQ(*table.rows[0].filtered_eligible_percent, 0.0);
  EXPECT_GT(*table.rows[0].raw_eligible_percent, 0.0);
  EXPECT_EQ(*table.rows[1].filtered_eligible_percent, *table.rows[1].raw_eligible_percent);
  EXPECT_EQ(result.levels[0].excluded_vertices, (std::vector<std::size_t>{cad.vertexCount(), 0}));
}

TEST(SensitivityStudy, BadInputIsAnInputError) {
  const TriangleMesh cad = ellipsoid();
  SensitivityParameters params = smallStudy();
  params.noise_levels = {0.5, -0.25};
  EXPECT_THROW(runSensitivityStudy(cad, "e", params, perfect(cad, params.rules)), InputError);
  params.noise_levels = {};
  EXPECT_THROW(runSensitivityStudy(cad, "e", params, perfect(cad, params.rules)), InputError);
  params = smallStudy();
  params.spacing_m = std::nan("");
  EXPECT_THROW(runSensitivityStudy(cad, "e", params, perfect(cad, params.rules)), InputError);
  params = smallStudy();
  params.rules = {};
  EXPECT_THROW(runSensitivityStudy(cad, "e", params, perfect(cad, params.rules)), InputError);
  EXPECT_EQ(sensitivityDatasetName("bun", 0.5, "default"), "bun noise=0.50x default");
}

}  // namespace
}  // namespace icrkit::eval
