// The Fig. 6 render of one grasp: identical meshes show intersection and no
// false positive; a displaced reconstruction shows false positives.

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/grasp_regions.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/report/grasp_render.hpp>

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace icrkit::report {
namespace {

using namespace icrkit::eval;

std::size_t pixelsOf(const RgbImage& image, const Eigen::Vector3f& colour, int tolerance) {
  std::size_t count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = &image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x)];
      // Shading darkens the albedo: compare hue by the channel ratios to the brightest.
      const float peak = std::max({p[0], p[1], p[2]}) / 255.0f;
      const float reference = colour.maxCoeff();
      if (peak < 0.15f) continue;
      bool same = true;
      for (int c = 0; c < 3; ++c)
        same = same && std::abs(p[c] / 255.0f / peak - colour[c] / reference) * 255.0f <= tolerance;
      count += same;
    }
  return count;
}

TEST(GraspRender, IdenticalMeshesShowIntersectionButNoFalsePositive) {
  TriangleMesh mesh = makeIcosphere(4, 0.04);
  for (auto& p : mesh.vertices.positions) p = p.cwiseProduct(Eigen::Vector3d(1.4, 1.0, 0.8));
  computeVertexNormals(mesh);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 2;
  const DatasetMeshes meshes{"same", &mesh, &mesh, &mesh};
  const DatasetExperiment experiment(meshes, config);
  const auto records = experiment.run(0, experiment.itemCount());
  ASSERT_TRUE(records.front().evaluated);
  const GraspRegions regions = regrowRegions(meshes, config, records.front());
  GraspRenderParameters params;
  params.view_width = 200;
  params.view_height = 150;
  const RgbImage image = renderGraspComparison(mesh, regions.cad, records.front().cad_contacts, mesh, regions.filtered,
                                               records.front().filtered.contacts, "filtered", params);
  EXPECT_EQ(image.width, 3 * 200);
  EXPECT_GT(image.height, 2 * 150);
  const ComparisonPalette palette;
  EXPECT_GT(pixelsOf(image, palette.intersection, 12), 100u);
  // The legend's swatch is the only vermillion allowed.
  EXPECT_LT(pixelsOf(image, palette.false_positive, 12), 400u);

  // Regions of another grasp drawn on the "reconstruction": mostly false positive.
  ASSERT_TRUE(records.back().evaluated);
  const GraspRegions other = regrowRegions(meshes, config, records.back());
  const RgbImage wrong = renderGraspComparison(mesh, regions.cad, records.front().cad_contacts, mesh, other.filtered,
                                               records.back().filtered.contacts, "filtered", params);
  EXPECT_GT(pixelsOf(wrong, palette.false_positive, 12), pixelsOf(image, palette.false_positive, 12) + 100);
}

TEST(GraspRender, RegionViewsOfOneMesh) {
  TriangleMesh mesh = makeIcosphere(3, 0.04);
  computeVertexNormals(mesh);
  OrbitParameters orbit;
  orbit.count = 3;
  const std::vector<RenderCamera> cameras = orbitCameras(mesh, orbit);
  RenderStyle style;
  style.width = 120;
  style.height = 90;
  style.samples_per_axis = 1;
  std::vector<int> region;
  for (int v = 0; v < 40; ++v) region.push_back(v);
  std::size_t steps = 0;
  const RegionPicture picture =
      renderRegionViews(mesh, {2}, {region}, {region.front()}, cameras, style, 0, true,
                        [&](const std::string& stage, std::size_t, std::size_t) { steps += stage == "render"; });
  EXPECT_EQ(steps, 3u);
  EXPECT_EQ(picture.columns, 2) << "about square: ceil(sqrt(3))";
  EXPECT_EQ(picture.image.width, 2 * 120);
  EXPECT_GT(picture.image.height, 2 * 90) << "two rows and the legend";
  ASSERT_EQ(picture.central_points.size(), 1u);
  EXPECT_GE(picture.central_points[0], 0);
  EXPECT_LT(picture.central_points[0], 40);
  const RegionPicture plain = renderRegionViews(mesh, {}, {}, {}, cameras, style, 5, false);
  EXPECT_EQ(plain.columns, 3) << "at most one column per view";
  EXPECT_THROW(renderRegionViews(mesh, {0, 1}, {region}, {}, cameras, style, 0, true), InputError);
}

TEST(GraspRender, RendersOfTheFirstEvaluatedGrasps) {
  TriangleMesh mesh = makeIcosphere(3, 0.04);
  for (auto& p : mesh.vertices.positions) p = p.cwiseProduct(Eigen::Vector3d(1.4, 1.0, 0.8));
  computeVertexNormals(mesh);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 3;
  const DatasetMeshes meshes{"same", &mesh, &mesh, &mesh};
  const DatasetExperiment experiment(meshes, config);
  const auto records = experiment.run(0, experiment.itemCount());
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("icrkit_renders_" + std::to_string(::getpid()));
  const std::vector<std::string> files = writeGraspRenders(dir.string(), meshes, config, records, 1);
  ASSERT_EQ(files.size(), 2u) << "filtered and raw of one grasp";
  EXPECT_EQ(files[0], RunFolder{dir.string()}.render(records.front(), "filtered"));
  EXPECT_TRUE(std::filesystem::exists(files[1]));
  EXPECT_TRUE(writeGraspRenders(dir.string(), meshes, config, records, 0).empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace icrkit::report
