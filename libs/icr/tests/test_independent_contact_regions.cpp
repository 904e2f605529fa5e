#include <icrkit/core/error.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include "test_meshes.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <random>
#include <set>

using namespace icrkit;
using namespace icrkit::icr;

namespace {

// Contacts at the six face centres of the cube-sphere: +x, -x, +y, -y, +z, -z.
std::vector<int> sixAxisContacts(const TriangleMesh& mesh) {
  std::vector<int> contacts;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {1, -1}) contacts.push_back(test::nearestVertex(mesh, sign * Eigen::Vector3d::Unit(axis)));
  return contacts;
}

// Mirrors vertex v in the plane through the origin normal to `axis`.
int mirrored(const TriangleMesh& mesh, int v, int axis) {
  Eigen::Vector3d p = mesh.vertices.positions[static_cast<std::size_t>(v)];
  p[axis] = -p[axis];
  return test::nearestVertex(mesh, p);
}

std::vector<int> mirroredRegion(const TriangleMesh& mesh, const std::vector<int>& region, int axis) {
  std::vector<int> out;
  for (int v : region) out.push_back(mirrored(mesh, v, axis));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(IndependentContactRegions, SymmetricGraspGivesSymmetricRegions) {
  const TriangleMesh mesh = test::cubeSphere(8);
  const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
  // Two generic contacts and their mirror images in the plane x = 0. (A grasp
  // with more symmetry puts wrenches exactly on hull facets, where qhull's
  // choice of which coplanar point becomes a vertex breaks the tie arbitrarily.)
  const int a = test::nearestVertex(mesh, Eigen::Vector3d(0.8, 0.3, 0.52).normalized());
  const int b = test::nearestVertex(mesh, Eigen::Vector3d(0.5, -0.6, -0.62).normalized());
  const std::vector<int> contacts{a, b, mirrored(mesh, a, 0), mirrored(mesh, b, 0)};
  IcrParameters params;
  params.alpha = 0.5;
  const IcrResult result = computeIndependentContactRegions(object, contacts, params);
  ASSERT_EQ(result.regions.size(), 4u);
  // The linearised friction cone is symmetric under the mirror planes of the
  // axes, and the wrench map (f, t) -> (M f, -M t) is an isometry, so each
  // region mirrors onto its partner's.
  for (std::size_t f = 0; f < 2; ++f) {
    const ContactRegion& original = result.regions[f];
    const ContactRegion& image = result.regions[f + 2];
    EXPECT_GT(original.vertices.size(), 1u);
    EXPECT_TRUE(std::binary_search(original.vertices.begin(), original.vertices.end(), original.contact));
    EXPECT_EQ(mirroredRegion(mesh, original.vertices, 0), image.vertices) << "finger " << f;
    EXPECT_NEAR(original.area_m2, image.area_m2, 1e-12);
  }
  // Breadth-first growth finds a connected subset of the full-mode region.
  params.mode = GrowthMode::Full;
  const IcrResult full = computeIndependentContactRegions(object, contacts, params);
  for (std::size_t f = 0; f < 4; ++f)
    EXPECT_TRUE(std::includes(full.regions[f].vertices.begin(), full.regions[f].vertices.end(),
                              result.regions[f].vertices.begin(), result.regions[f].vertices.end()));
  // Only the visited vertices had their wrenches computed.
  EXPECT_LT(result.vertices_tested, mesh.vertexCount());
  EXPECT_EQ(full.vertices_tested, mesh.vertexCount());  // a contact is tested for the other fingers
}

TEST(IndependentContactRegions, ExcludedVerticesNeverJoinARegion) {
  const TriangleMesh mesh = test::cubeSphere(8);
  const std::vector<int> contacts = sixAxisContacts(mesh);
  const IcrResult free = computeIndependentContactRegions(GraspableObject::withDefaultFrame(mesh), contacts);
  std::vector<std::uint8_t> mask(mesh.vertexCount(), 0);
  std::set<int> excluded;
  for (const ContactRegion& r : free.regions)
    for (int v : r.vertices)
      if (v != r.contact && v % 2 == 0) {
        mask[static_cast<std::size_t>(v)] = 1;
        excluded.insert(v);
      }
  ASSERT_FALSE(excluded.empty());
  for (GrowthMode mode : {GrowthMode::BreadthFirst, GrowthMode::Full}) {
    IcrParameters params;
    params.mode = mode;
    const IcrResult masked = computeIndependentContactRegions(GraspableObject::withDefaultFrame(mesh, mask), contacts, params);
    for (const ContactRegion& r : masked.regions)
      for (int v : r.vertices) EXPECT_FALSE(excluded.count(v)) << v;
  }
  // An excluded prototype contact is refused.
  mask[static_cast<std::size_t>(contacts[0])] = 1;
  EXPECT_THROW(computeIndependentContactRegions(GraspableObject::withDefaultFrame(mesh, mask), contacts), InputError);
}

TEST(IndependentContactRegions, BadInputIsRefusedClearly) {
  const TriangleMesh mesh = test::cubeSphere(6);
  const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
  const std::vector<int> contacts = sixAxisContacts(mesh);
  auto message = [&](const std::vector<int>& c, const IcrParameters& p) {
    try {
      computeIndependentContactRegions(object, c, p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  IcrParameters params;
  EXPECT_NE(message({contacts[0]}, params).find("at least 2 contacts"), std::string::npos);
  EXPECT_NE(message({contacts[0], contacts[1], contacts[0]}, params).find("used by contacts"), std::string::npos);
  EXPECT_NE(message({contacts[0], static_cast<int>(mesh.vertexCount())}, params).find("expected 0.."), std::string::npos);
  // Four neighbouring vertices cannot hold anything in force closure.
  const auto& adjacency = object.adjacency();
  std::vector<int> cluster{contacts[0]};
  for (const int* it = adjacency.begin(static_cast<std::size_t>(contacts[0])); cluster.size() < 4; ++it) cluster.push_back(*it);
  EXPECT_NE(message(cluster, params).find("not force closure"), std::string::npos);
  params.alpha = 1.5;
  EXPECT_NE(message(contacts, params).find("alpha"), std::string::npos);
  params = IcrParameters();
  params.tws_radius = 10.0;
  EXPECT_NE(message(contacts, params).find("inside the GWS"), std::string::npos);
  // Frictionless grasps need at least 7 contacts (7 wrenches for a 6-D hull).
  params = IcrParameters();
  params.contact_model.type = ContactType::Frictionless;
  EXPECT_NE(message(contacts, params).find("at least 7"), std::string::npos);
  // No normals.
  TriangleMesh bare = mesh;
  bare.vertices.normals.clear();
  EXPECT_THROW(GraspableObject::withDefaultFrame(bare), InputError);
}

TEST(IndependentContactRegions, RegionAreaCountsOnlyFullTriangles) {
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {Triangle(0, 1, 2), Triangle(0, 2, 3)};
  EXPECT_DOUBLE_EQ(regionArea(m, {0, 1, 2, 3}), 1.0);
  EXPECT_DOUBLE_EQ(regionArea(m, {0, 1, 2}), 0.5);
  EXPECT_DOUBLE_EQ(regionArea(m, {0, 2}), 0.0);
}

// The defining property: any grasp with one vertex from each region resists
// the task wrench space, i.e. its epsilon is at least the TWS radius.
TEST(IndependentContactRegions, EveryPickFromTheRegionsResistsTheTask) {
  struct Case {
    Eigen::Vector3d scale;
    ContactType type;
    std::size_t fingers;
    unsigned seed;
  };
  const Case cases[] = {{{1.0, 0.7, 0.5}, ContactType::Frictional, 4, 1},
                        {{0.6, 1.0, 0.8}, ContactType::Frictional, 5, 2},
                        {{1.0, 0.8, 0.6}, ContactType::SoftFinger, 4, 3}};
  constexpr int picks = 1000;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.seed);
    const TriangleMesh mesh = test::cubeSphere(8, c.scale);
    const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
    IcrParameters params;
    params.contact_model.type = c.type;
    params.contact_model.friction = 0.6;
    params.alpha = 0.5;
    // A random force-closure prototype with a reasonable epsilon.
    std::mt19937 rng(c.seed);
    const std::vector<int> contacts = test::randomForceClosureGrasp(object, params.contact_model, c.fingers, 0.05, rng, 10000);
    ASSERT_FALSE(contacts.empty());
    const IcrResult result = computeIndependentContactRegions(object, contacts, params);
    std::size_t total = 0;
    for (const ContactRegion& r : result.regions) total += r.vertices.size();
    EXPECT_GT(total, c.fingers);  // something grew

    std::vector<std::vector<int>> grasps(picks);
    for (auto& g : grasps)
      for (const ContactRegion& r : result.regions)
        g.push_back(r.vertices[std::uniform_int_distribution<std::size_t>(0, r.vertices.size() - 1)(rng)]);
    std::atomic<int> failures{0};
    tbb::parallel_for(0, picks, [&](int i) {
      std::vector<int> g = grasps[static_cast<std::size_t>(i)];
      std::set<int> distinct(g.begin(), g.end());
      if (distinct.size() < g.size()) return;  // regions may overlap; a repeated vertex is one finger less
      const GraspWrenchSpace gws = graspWrenchSpace(object, g, params.contact_model);
      if (!gws.force_closure || gws.epsilon < result.tws_radius - 1e-12) ++failures;
    });
    EXPECT_EQ(failures.load(), 0);

    // And where it must fail: with a task close to the GWS (alpha 0.95 and up)
    // the regions are tight, and a vertex just outside one (a neighbour that
    // did not qualify) breaks the guarantee for some pick.
    int broken = 0;
    for (double tight_alpha : {0.95, 0.99, 1.0}) {
      if (broken) break;
      params.alpha = tight_alpha;
      params.mode = GrowthMode::BreadthFirst;
      const IcrResult tight = computeIndependentContactRegions(object, contacts, params);
      params.mode = GrowthMode::Full;
      const IcrResult tight_full = computeIndependentContactRegions(object, contacts, params);
      int tried = 0;
      for (std::size_t f = 0; f < contacts.size() && broken == 0 && tried < 400; ++f) {
        const auto& region = tight_full.regions[f].vertices;
        for (int v : tight.regions[f].vertices) {
          for (const int* it = object.adjacency().begin(static_cast<std::size_t>(v));
               it != object.adjacency().end(static_cast<std::size_t>(v)) && broken == 0 && tried < 400; ++it) {
            if (std::binary_search(region.begin(), region.end(), *it)) continue;
            // First the other prototype contacts, then random picks of theirs.
            for (int trial = 0; trial < 10 && broken == 0; ++trial, ++tried) {
              std::vector<int> g;
              for (std::size_t k = 0; k < contacts.size(); ++k) {
                const auto& r = tight.regions[k].vertices;
                g.push_back(k == f ? *it
                            : trial == 0 ? contacts[k]
                                         : r[std::uniform_int_distribution<std::size_t>(0, r.size() - 1)(rng)]);
              }
              const GraspWrenchSpace gws = graspWrenchSpace(object, g, params.contact_model);
              if (!gws.force_closure || gws.epsilon < tight.tws_radius) ++broken;
            }
          }
        }
      }
    }
    EXPECT_GT(broken, 0) << "no vertex outside the regions broke the task guarantee";
  }
}
