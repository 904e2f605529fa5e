// Vertices that no face uses (points a reconstruction left unmeshed; the
// Stanford bunny's zippered mesh has 1,113): never a contact, never in a
// region, never a mapping target, whatever normal they carry, and without
// renumbering the others.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/grasp_transfer.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::icr {
namespace {

// `clean` with unreferenced vertices inserted before the given indices (an
// index past the end appends), carrying normals no check would accept.
struct StrayMesh {
  TriangleMesh mesh;
  std::vector<int> new_index;  // clean index -> index in `mesh`
  std::vector<int> strays;     // indices of the inserted vertices in `mesh`
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

std::vector<int> renumbered(const std::vector<int>& vertices, const std::vector<int>& new_index) {
  std::vector<int> out;
  for (const int v : vertices) out.push_back(new_index[static_cast<std::size_t>(v)]);
  return out;
}

ContactModel frictional() {
  ContactModel model;
  model.friction = 0.8;
  model.cone_edges = 8;
  return model;
}

// A sphere off the origin (so that a stray point far away would move the
// default frame's lambda) with strays: far away, at the centre, and one on
// top of vertex 5, which any nearest-point search would otherwise find.
struct Fixture {
  TriangleMesh clean = makeIcosphere(3, 0.05, Eigen::Vector3d(0.02, -0.01, 0.03));
  StrayMesh dirty = withStrays(clean, {{0, Eigen::Vector3d(3, 3, 3)},
                                       {5, clean.vertices.positions[5]},
                                       {200, Eigen::Vector3d(0.02, -0.01, 0.03)},
                                       {100000, Eigen::Vector3d(-1, 0, 0)}});
};

TEST(UnreferencedVertices, ValidationAndTheDefaultFrameIgnoreThem) {
  const Fixture f;
  ASSERT_EQ(f.dirty.strays, (std::vector<int>{0, 6, 202, 645}));
  for (const TorqueReference reference : {TorqueReference::Origin, TorqueReference::Centroid}) {
    const GraspableObject clean = GraspableObject::withDefaultFrame(f.clean, {}, reference);
    const GraspableObject dirty = GraspableObject::withDefaultFrame(f.dirty.mesh, {}, reference);
    EXPECT_EQ(dirty.frame().lambda, clean.frame().lambda);
    EXPECT_EQ(dirty.frame().reference_point, clean.frame().reference_point);
    EXPECT_EQ(dirty.unreferencedCount(), 4u);
    EXPECT_EQ(clean.unreferencedCount(), 0u);
    for (const int s : f.dirty.strays) {
      EXPECT_FALSE(dirty.referenced(static_cast<std::size_t>(s)));
      EXPECT_FALSE(dirty.eligible(static_cast<std::size_t>(s)));
    }
    EXPECT_TRUE(dirty.eligible(1));
  }
  // A used vertex still needs its unit normal, named in the error.
  TriangleMesh broken = f.dirty.mesh;
  broken.vertices.normals[7] = Eigen::Vector3d::Zero();
  try {
    GraspableObject::withDefaultFrame(broken);
    ADD_FAILURE() << "a zero normal on a used vertex was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.location(), "vertex 7");
  }
  // Points without faces are no surface to grasp.
  TriangleMesh points = f.clean;
  points.faces.clear();
  EXPECT_THROW(GraspableObject::withDefaultFrame(points), InputError);
  EXPECT_THROW(GraspableObject(points, WrenchFrame{}), InputError);
}

TEST(UnreferencedVertices, NeverSampledAndTheGraspsAreTheCleanMeshesRenumbered) {
  const Fixture f;
  GraspSamplingParameters params;
  params.count = 25;
  params.seed = 4;
  const auto clean = sampleForceClosureGrasps(GraspableObject::withDefaultFrame(f.clean), frictional(), params);
  const auto dirty = sampleForceClosureGrasps(GraspableObject::withDefaultFrame(f.dirty.mesh), frictional(), params);
  ASSERT_EQ(dirty.size(), params.count);
  ASSERT_EQ(clean.size(), dirty.size());
  for (std::size_t g = 0; g < dirty.size(); ++g) {
    EXPECT_EQ(dirty[g].contacts, renumbered(clean[g].contacts, f.dirty.new_index)) << g;
    EXPECT_EQ(dirty[g].epsilon, clean[g].epsilon) << g;
  }

  // Four fingers but only three vertices of faces left eligible: refused.
  std::vector<std::uint8_t> mask(f.dirty.mesh.vertexCount(), 1);
  for (const int s : f.dirty.strays) mask[static_cast<std::size_t>(s)] = 0;
  mask[1] = mask[2] = mask[3] = 0;
  EXPECT_THROW(sampleForceClosureGrasps(GraspableObject::withDefaultFrame(f.dirty.mesh, mask), frictional(), params),
               InputError);
}

TEST(UnreferencedVertices, RegionsAreThoseOfTheCleanMeshAndNeverHoldThem) {
  const Fixture f;
  const GraspableObject clean_object = GraspableObject::withDefaultFrame(f.clean);
  const GraspableObject dirty_object = GraspableObject::withDefaultFrame(f.dirty.mesh);
  GraspSamplingParameters sampling;
  sampling.count = 3;
  std::size_t compared = 0;
  for (const SampledGrasp& grasp : sampleForceClosureGrasps(clean_object, frictional(), sampling))
    for (const GrowthMode mode : {GrowthMode::BreadthFirst, GrowthMode::Full}) {
      IcrParameters params;
      params.contact_model = frictional();
      params.mode = mode;
      const IcrResult clean = computeIndependentContactRegions(clean_object, grasp.contacts, params);
      const IcrResult dirty = computeIndependentContactRegions(
          dirty_object, renumbered(grasp.contacts, f.dirty.new_index), params);
      EXPECT_EQ(dirty.epsilon, clean.epsilon);
      EXPECT_EQ(dirty.vertices_tested, clean.vertices_tested);
      ASSERT_EQ(dirty.regions.size(), clean.regions.size());
      for (std::size_t r = 0; r < clean.regions.size(); ++r) {
        EXPECT_EQ(dirty.regions[r].vertices, renumbered(clean.regions[r].vertices, f.dirty.new_index));
        EXPECT_EQ(dirty.regions[r].area_m2, clean.regions[r].area_m2);
        for (const int s : f.dirty.strays)
          EXPECT_FALSE(std::binary_search(dirty.regions[r].vertices.begin(), dirty.regions[r].vertices.end(), s));
        ++compared;
      }
    }
  EXPECT_EQ(compared, 2u * 3u * 4u);
}

TEST(UnreferencedVertices, AContactOnOneIsRefusedNamingTheVertex) {
  const Fixture f;
  const GraspableObject object = GraspableObject::withDefaultFrame(f.dirty.mesh);
  GraspSamplingParameters sampling;
  sampling.count = 1;
  std::vector<int> contacts = sampleForceClosureGrasps(object, frictional(), sampling).front().contacts;
  contacts[2] = f.dirty.strays[2];
  try {
    computeIndependentContactRegions(object, contacts);
    ADD_FAILURE() << "a contact on an unreferenced vertex was accepted";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("contact 2 (vertex 202)"), std::string::npos) << message;
    EXPECT_NE(message.find("no face"), std::string::npos) << message;
  }
}

TEST(UnreferencedVertices, GraspTransferNeverMapsOntoThem) {
  const Fixture f;
  // The stray on top of vertex 5 is as near every line through it as vertex
  // 5 itself, and comes first by index: only the rule keeps it out.
  const NormalLineMapping clean(f.clean);
  const NormalLineMapping dirty(f.dirty.mesh);
  EXPECT_EQ(dirty.searchRadius(), clean.searchRadius());
  for (std::size_t v = 0; v < f.clean.vertexCount(); ++v) {
    const int image = dirty.map(f.clean.vertices.positions[v], f.clean.vertices.normals[v]);
    ASSERT_EQ(image, f.dirty.new_index[v]) << v;
  }
  const std::vector<int> moved = transferGrasp(f.clean, {5, 9, 300}, f.dirty.mesh);
  EXPECT_EQ(moved, renumbered({5, 9, 300}, f.dirty.new_index));
  // A stray is no contact to move.
  EXPECT_THROW(transferGrasp(f.dirty.mesh, {1, f.dirty.strays[1]}, f.clean), InputError);
  // A point set (no faces) still offers every point.
  TriangleMesh points = f.dirty.mesh;
  points.faces.clear();
  NormalLineMappingParameters params;
  params.search_radius = 0.01;
  EXPECT_EQ(NormalLineMapping(points, params).map(f.clean.vertices.positions[5], f.clean.vertices.normals[5]),
            f.dirty.strays[1]);
}

// The real file: 35,947 vertices, 1,113 of them used by no face, no normals.
TEST(UnreferencedVertices, TheStanfordBunnyAsItIs) {
  const auto path = std::filesystem::path(ICRKIT_SHARED_DATA_DIR) / "stanford-bunny" / "bun_zipper.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  TriangleMesh bunny = io::readTriangleMesh(path.string());
  ASSERT_EQ(meshComponents(bunny).unreferenced_vertices, 1113u);
  computeVertexNormals(bunny);
  for (std::size_t v = 0; v < bunny.vertexCount(); ++v)
    ASSERT_NEAR(bunny.vertices.normals[v].norm(), 1.0, 1e-9) << "vertex " << v;

  const GraspableObject object = GraspableObject::withDefaultFrame(bunny, {}, TorqueReference::Centroid);
  EXPECT_EQ(object.unreferencedCount(), 1113u);
  GraspSamplingParameters sampling;
  sampling.count = 5;
  const auto grasps = sampleForceClosureGrasps(object, frictional(), sampling);
  ASSERT_EQ(grasps.size(), sampling.count);
  for (const SampledGrasp& grasp : grasps)
    for (const int c : grasp.contacts) EXPECT_TRUE(object.referenced(static_cast<std::size_t>(c))) << c;
  IcrParameters params;
  params.contact_model = frictional();
  const IcrResult result = computeIndependentContactRegions(object, grasps.front().contacts, params);
  ASSERT_EQ(result.regions.size(), 4u);
  for (const ContactRegion& region : result.regions) {
    EXPECT_GE(region.vertices.size(), 1u);
    for (const int v : region.vertices) EXPECT_TRUE(object.referenced(static_cast<std::size_t>(v))) << v;
  }
}

}  // namespace
}  // namespace icrkit::icr
