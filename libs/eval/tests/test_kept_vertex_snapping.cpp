// Snapping contacts off excluded vertices, on a flat grid whose nearest kept
// vertices are known by construction.

#include <icrkit/core/error.hpp>
#include <icrkit/eval/kept_vertex_snapping.hpp>

#include <gtest/gtest.h>

#include "eval_test_meshes.hpp"

#include <cstdint>
#include <limits>

namespace icrkit::eval {
namespace {

// A power of two, so that every grid distance below is exact.
constexpr double kStep = 1.0 / 1024.0;

// 5 x 5 grid, vertex (i, j) at index 5 j + i, normals up; plus one vertex
// (index 25) that no face uses, a quarter step from the centre vertex 12.
TriangleMesh gridWithStray() {
  TriangleMesh mesh = test::flatGrid(5, 5, kStep);
  mesh.vertices.positions.push_back(mesh.vertices.positions[12] + Eigen::Vector3d(0.25 * kStep, 0.0, 0.0));
  mesh.vertices.normals.assign(mesh.vertexCount(), Eigen::Vector3d::UnitZ());
  return mesh;
}

std::vector<std::uint8_t> maskOf(const TriangleMesh& mesh, const std::vector<int>& excluded) {
  std::vector<std::uint8_t> mask(mesh.vertexCount(), 0);
  for (const int v : excluded) mask[static_cast<std::size_t>(v)] = 1;
  return mask;
}

TEST(KeptVertexSnapping, ExcludedContactMovesToTheNearestKeptVertexTiesToTheLowerIndex) {
  const TriangleMesh mesh = gridWithStray();
  const auto object = icr::GraspableObject::withDefaultFrame(mesh, maskOf(mesh, {12, 13}));
  const KeptVertexSnapping snapping(object, 1.5 * kStep);
  // Vertex 12 = (2, 2): the stray vertex 25 is nearer but used by no face;
  // 13 is excluded; 7, 11 and 17 are one step away: the lowest index wins.
  const SnappedContacts snapped = snapping.snap({12, 0, 24});
  EXPECT_EQ(snapped.reason, "");
  EXPECT_EQ(snapped.contacts, (std::vector<int>{7, 0, 24}));
  EXPECT_EQ(snapped.move_distances_m, (std::vector<double>{kStep, 0.0, 0.0}));
  // Kept contacts stay, even when a kept vertex is nearer to another one.
  EXPECT_EQ(snapping.snap({6, 18}).contacts, (std::vector<int>{6, 18}));
  EXPECT_EQ(snapping.radius(), 1.5 * kStep);
}

TEST(KeptVertexSnapping, TheRadiusIsInclusive) {
  const TriangleMesh mesh = gridWithStray();
  const auto object = icr::GraspableObject::withDefaultFrame(mesh, maskOf(mesh, {12}));
  EXPECT_EQ(KeptVertexSnapping(object, kStep).snap({12}).contacts, (std::vector<int>{7}));
}

TEST(KeptVertexSnapping, NoKeptVertexWithinReachFailsWithAReason) {
  const TriangleMesh mesh = gridWithStray();
  const auto object = icr::GraspableObject::withDefaultFrame(mesh, maskOf(mesh, {12}));
  const SnappedContacts snapped = KeptVertexSnapping(object, 0.5 * kStep).snap({0, 12});
  EXPECT_TRUE(snapped.contacts.empty());
  EXPECT_TRUE(snapped.move_distances_m.empty());
  EXPECT_EQ(snapped.reason, "contact 1: no kept vertex within 0.488 mm of excluded vertex 12");

  // Nothing kept at all: every excluded contact fails.
  std::vector<int> all(25);
  for (int v = 0; v < 25; ++v) all[static_cast<std::size_t>(v)] = v;
  const auto nothing_kept = icr::GraspableObject::withDefaultFrame(mesh, maskOf(mesh, all));
  EXPECT_EQ(KeptVertexSnapping(nothing_kept, 10 * kStep).snap({3}).reason.rfind("contact 0: no kept vertex", 0), 0u);
}

TEST(KeptVertexSnapping, TwoContactsEndingOnOneVertexFail) {
  const TriangleMesh mesh = gridWithStray();
  // 12 = (2, 2) goes to 7 = (2, 1) (lowest of 7, 11, 13, 17); 2 = (2, 0),
  // with 1 and 3 excluded, has only 7 within one step.
  const auto object = icr::GraspableObject::withDefaultFrame(mesh, maskOf(mesh, {1, 2, 3, 12}));
  const SnappedContacts snapped = KeptVertexSnapping(object, 1.2 * kStep).snap({12, 20, 2});
  EXPECT_EQ(snapped.contacts, (std::vector<int>{7, 20, 7}));
  EXPECT_EQ(snapped.reason, "contact 0 and contact 2 end on the same vertex after snapping");
}

TEST(KeptVertexSnapping, BadInputIsAnInputError) {
  const TriangleMesh mesh = gridWithStray();
  const auto object = icr::GraspableObject::withDefaultFrame(mesh);
  EXPECT_THROW(KeptVertexSnapping(object, 0.0), InputError);
  EXPECT_THROW(KeptVertexSnapping(object, -1.0), InputError);
  EXPECT_THROW(KeptVertexSnapping(object, std::numeric_limits<double>::quiet_NaN()), InputError);
  EXPECT_THROW(KeptVertexSnapping(object, kStep).snap({0, 26}), InputError);
  EXPECT_THROW(KeptVertexSnapping(object, kStep).snap({-1}), InputError);
}

}  // namespace
}  // namespace icrkit::eval
