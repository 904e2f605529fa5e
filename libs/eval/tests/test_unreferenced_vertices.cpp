// Vertices that no face uses, in every mesh of an evaluation: the experiment,
// the alignment and the renders give what the meshes without them give,
// whatever normals those vertices carry.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/grasp_regions.hpp>
#include <icrkit/eval/rigid_alignment.hpp>
#include <icrkit/report/mesh_render.hpp>

#include "experiment_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::eval {
namespace {

using test::ellipsoid;
using test::noisyCopy;
using test::recordLines;

// `clean` with unreferenced vertices inserted before the given indices (past
// the end: appended), their normals zero, too long or NaN.
struct StrayMesh {
  TriangleMesh mesh;
  std::vector<int> new_index;  // clean index -> index in `mesh`
  std::vector<int> strays;
};

StrayMesh withStrays(const TriangleMesh& clean, const std::vector<std::pair<std::size_t, Eigen::Vector3d>>& strays) {
  const std::size_t n = clean.vertexCount();
  const std::vector<Eigen::Vector3d> garbage{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 7),
                                             Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())};
  StrayMesh out;
  out.mesh = clean;
  out.mesh.vertices.resize(n + strays.size());
  for (std::size_t s = 0; s < strays.size(); ++s) {
    out.mesh.vertices.positions[n + s] = strays[s].second;
    if (out.mesh.vertices.hasNormals()) out.mesh.vertices.normals[n + s] = garbage[s % garbage.size()];
  }
  std::vector<std::size_t> order;
  out.new_index.assign(n, -1);
  for (std::size_t v = 0; v <= n; ++v) {
    for (std::size_t s = 0; s < strays.size(); ++s)
      if (std::min(strays[s].first, n) == v) {
        out.strays.push_back(static_cast<int>(order.size()));
        order.push_back(n + s);
      }
    if (v == n) break;
    out.new_index[v] = static_cast<int>(order.size());
    order.push_back(v);
  }
  out.mesh.vertices.select(order);
  for (Triangle& f : out.mesh.faces)
    for (int k = 0; k < 3; ++k) f[k] = out.new_index[static_cast<std::size_t>(f[k])];
  return out;
}

// Strays where they would do harm if counted: far away (the frame, the
// framing), on top of surface vertices (every nearest-vertex search), and
// inside.
StrayMesh strayed(const TriangleMesh& clean) {
  const auto& p = clean.vertices.positions;
  return withStrays(clean, {{0, Eigen::Vector3d(0.5, 0.5, 0.5)},
                            {3, p[3]},
                            {40, p[41]},
                            {clean.vertexCount() / 2, Eigen::Vector3d::Zero()},
                            {clean.vertexCount(), p.back()}});
}

std::vector<int> renumbered(const std::vector<int>& vertices, const std::vector<int>& new_index) {
  std::vector<int> out;
  for (const int v : vertices) out.push_back(new_index[static_cast<std::size_t>(v)]);
  return out;
}

// The clean run's records with their vertex indices moved to the strayed
// meshes' numbering, as JSON lines.
std::vector<std::string> renumberedLines(std::vector<GraspRecord> records, const StrayMesh& cad, const StrayMesh& raw,
                                         const StrayMesh& filtered) {
  std::vector<std::string> lines;
  for (GraspRecord& r : records) {
    r.cad_contacts = renumbered(r.cad_contacts, cad.new_index);
    r.raw.contacts = renumbered(r.raw.contacts, raw.new_index);
    r.filtered.contacts = renumbered(r.filtered.contacts, filtered.new_index);
    if (r.filtered.snapped) r.filtered.snapped->contacts = renumbered(r.filtered.snapped->contacts, filtered.new_index);
    lines.push_back(toJsonLine(r));
  }
  return lines;
}

TEST(UnreferencedVertices, TheExperimentGivesTheCleanMeshesRecords) {
  const TriangleMesh cad = ellipsoid(3);
  const TriangleMesh raw = noisyCopy(cad, 3e-4, 5);
  TriangleMesh filtered = noisyCopy(cad, 2e-4, 6);
  for (std::size_t v = 0; v < filtered.vertexCount(); v += 13) filtered.vertices.setFlag("excluded", v, true);
  const StrayMesh cad_s = strayed(cad), raw_s = strayed(raw), filtered_s = strayed(filtered);
  for (const int s : filtered_s.strays) EXPECT_FALSE(filtered_s.mesh.vertices.flag("excluded", static_cast<std::size_t>(s)));

  ExperimentConfig config;
  config.finger_counts = {4, 5};
  config.grasps_per_set = 3;
  const DatasetExperiment clean({"x", &cad, &raw, &filtered}, config);
  const DatasetExperiment dirty({"x", &cad_s.mesh, &raw_s.mesh, &filtered_s.mesh}, config);
  EXPECT_EQ(dirty.cadLambda(), clean.cadLambda());
  ASSERT_EQ(dirty.itemCount(), clean.itemCount());
  const auto clean_records = clean.run(0, clean.itemCount());
  const auto dirty_records = dirty.run(0, dirty.itemCount());
  std::size_t evaluated = 0;
  for (const GraspRecord& r : clean_records) evaluated += r.evaluated;
  EXPECT_GT(evaluated, 0u);
  EXPECT_EQ(recordLines(dirty_records), renumberedLines(clean_records, cad_s, raw_s, filtered_s));

  // Renders and reports regrow the regions: free of strays.
  const auto strayFree = [](const std::vector<std::vector<int>>& regions, const StrayMesh& mesh) {
    for (const std::vector<int>& region : regions)
      for (const int v : region)
        if (std::count(mesh.strays.begin(), mesh.strays.end(), v) > 0) return false;
    return !regions.empty();
  };
  for (const GraspRecord& r : dirty_records) {
    if (!r.evaluated) continue;
    const GraspRegions regions = regrowRegions({"x", &cad_s.mesh, &raw_s.mesh, &filtered_s.mesh}, config, r);
    EXPECT_TRUE(strayFree(regions.cad, cad_s));
    EXPECT_TRUE(strayFree(regions.raw, raw_s));
    EXPECT_TRUE(strayFree(regions.filtered, filtered_s));
  }
}

TEST(UnreferencedVertices, AlignmentAndRendersIgnoreThem) {
  const TriangleMesh cad = ellipsoid(3);
  TriangleMesh raw = noisyCopy(cad, 3e-4, 5);
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.translation() = Eigen::Vector3d(0.002, -0.001, 0.001);
  transformMesh(raw, offset);
  const StrayMesh raw_s = strayed(raw);
  const AlignmentResult clean = alignToCad(raw, cad);
  const AlignmentResult dirty = alignToCad(raw_s.mesh, cad);
  EXPECT_EQ(dirty.transform.matrix(), clean.transform.matrix());
  EXPECT_EQ(dirty.pairs, clean.pairs);

  const StrayMesh cad_s = strayed(cad);
  const report::BoundingSphere a = report::boundingSphere(cad), b = report::boundingSphere(cad_s.mesh);
  EXPECT_EQ(a.centre, b.centre);
  EXPECT_EQ(a.radius, b.radius);
  report::RenderStyle style;
  style.width = 96;
  style.height = 72;
  const std::vector<report::RenderCamera> cameras = report::orbitCameras(cad_s.mesh);
  ASSERT_EQ(cameras.size(), report::orbitCameras(cad).size());
  const std::vector<int> region{10, 11, 12, 50, 51};
  report::SurfaceColours clean_colours, dirty_colours;
  clean_colours.per_vertex = report::regionColours(cad, {0}, {region}, style.base_colour);
  dirty_colours.per_vertex = report::regionColours(cad_s.mesh, {0}, {renumbered(region, cad_s.new_index)}, style.base_colour);
  const report::MeshRenderer clean_renderer(cad), dirty_renderer(cad_s.mesh);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    EXPECT_EQ(cameras[c].eye, report::orbitCameras(cad)[c].eye);
    EXPECT_EQ(dirty_renderer.render(cameras[c], style, dirty_colours).rgb,
              clean_renderer.render(cameras[c], style, clean_colours).rgb)
        << cameras[c].name;
  }
}

TEST(UnreferencedVertices, ZeroNormalsOnThemPassAndOnUsedVerticesFail) {
  const TriangleMesh cad = ellipsoid(2);
  const StrayMesh cad_s = strayed(cad);
  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 1;
  EXPECT_NO_THROW(DatasetExperiment({"x", &cad_s.mesh, &cad_s.mesh, &cad_s.mesh}, config));
  TriangleMesh broken = cad_s.mesh;
  broken.vertices.normals[static_cast<std::size_t>(cad_s.new_index[8])] = Eigen::Vector3d::Zero();
  try {
    DatasetExperiment({"x", &cad_s.mesh, &broken, &cad_s.mesh}, config);
    ADD_FAILURE() << "a zero normal on a used vertex was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "raw mesh");
    EXPECT_EQ(error.location(), "vertex " + std::to_string(cad_s.new_index[8]));
  }
}

// The real file, read as it is: 1,113 of its vertices are used by no face,
// and it has no normals. The records are those of the mesh without them.
TEST(UnreferencedVertices, TheStanfordBunnyWithAndWithoutItsStrays) {
  const auto path = std::filesystem::path(ICRKIT_SHARED_DATA_DIR) / "stanford-bunny" / "bun_zipper.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  TriangleMesh bunny = io::readTriangleMesh(path.string());
  const std::vector<std::uint8_t> referenced = referencedVertices(bunny);
  std::vector<int> new_index(bunny.vertexCount(), -1);
  TriangleMesh stripped;
  for (std::size_t v = 0; v < bunny.vertexCount(); ++v)
    if (referenced[v]) {
      new_index[v] = static_cast<int>(stripped.vertices.positions.size());
      stripped.vertices.positions.push_back(bunny.vertices.positions[v]);
    }
  for (Triangle f : bunny.faces) {
    for (int k = 0; k < 3; ++k) f[k] = new_index[static_cast<std::size_t>(f[k])];
    stripped.faces.push_back(f);
  }
  ASSERT_EQ(bunny.vertexCount() - stripped.vertexCount(), 1113u);
  computeVertexNormals(bunny);
  computeVertexNormals(stripped);

  ExperimentConfig config;
  config.finger_counts = {4};
  config.grasps_per_set = 2;
  const DatasetExperiment as_is({"bunny", &bunny, &bunny, &bunny}, config);
  const DatasetExperiment clean({"bunny", &stripped, &stripped, &stripped}, config);
  const auto records = as_is.run(0, as_is.itemCount());
  ASSERT_EQ(records.size(), 2u);
  // Back to the file's numbering: the stripped mesh keeps the vertex order.
  std::vector<int> old_index(stripped.vertexCount());
  for (std::size_t v = 0; v < new_index.size(); ++v)
    if (new_index[v] >= 0) old_index[static_cast<std::size_t>(new_index[v])] = static_cast<int>(v);
  StrayMesh numbering;
  numbering.new_index = old_index;
  EXPECT_EQ(recordLines(records), renumberedLines(clean.run(0, clean.itemCount()), numbering, numbering, numbering));
  for (const GraspRecord& r : records) EXPECT_TRUE(r.evaluated) << r.raw.reason;
}

}  // namespace
}  // namespace icrkit::eval
