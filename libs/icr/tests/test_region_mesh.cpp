// The regions painted on their mesh (region_mesh.hpp) and a grasp given as
// points snapped to contact vertices (contact_snapping.hpp).

#include <icrkit/icr/contact_snapping.hpp>
#include <icrkit/icr/region_mesh.hpp>

#include <icrkit/core/error.hpp>

#include "test_meshes.hpp"

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace icrkit::icr {
namespace {

TEST(RegionMesh, ColoursAndAttributes) {
  const TriangleMesh mesh = test::unitCube();
  ContactRegion a;
  a.finger = 0;
  a.vertices = {0, 1, 2};
  a.recommended.vertex = 1;
  ContactRegion b;
  b.finger = 1;
  b.vertices = {2, 3};
  b.recommended.vertex = 3;
  const TriangleMesh out = regionMesh(mesh, {a, b});
  EXPECT_EQ(out.faces, mesh.faces);
  const auto& region = out.vertices.attributes.get("region").values;
  const auto& recommended = out.vertices.attributes.get("recommended").values;
  EXPECT_EQ(region, (std::vector<double>{0, 0, 0, 1, -1, -1, -1, -1})) << "vertex 2: the lower finger index";
  EXPECT_EQ(recommended, (std::vector<double>{-1, 0, -1, 1, -1, -1, -1, -1}));
  EXPECT_EQ(out.vertices.colours[1], (Colour{0, 0, 0})) << "recommended contacts are black";
  EXPECT_EQ(out.vertices.colours[0], (Colour{31, 119, 180}));
  EXPECT_EQ(out.vertices.colours[5], (Colour{190, 190, 190})) << "outside every region: grey";

  ContactRegion far;
  far.finger = 2;
  far.vertices = {8};
  EXPECT_EQ(test::expectInputError([&] { regionMesh(mesh, {far}); }).location(), "finger 2");
}

TEST(ContactSnapping, NearestVertexOfAFace) {
  TriangleMesh mesh = test::unitCube();
  mesh.vertices.positions.push_back(Eigen::Vector3d(0.1, 0.1, 0.1));  // used by no face
  const SnappedContacts snapped =
      snapToFaceVertices(mesh, {Eigen::Vector3d(0.05, 0.05, 0.05), Eigen::Vector3d(1.1, 1.0, 1.0)});
  EXPECT_EQ(snapped.vertices, (std::vector<int>{0, 7})) << "the unreferenced vertex 8 attracts nothing";
  EXPECT_NEAR(snapped.distances_m[1], 0.1, 1e-12);
  EXPECT_EQ(test::expectInputError([&] {
              snapToFaceVertices(mesh, {Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0)});
            }).location(),
            "point 1");
  TriangleMesh points_only = mesh;
  points_only.faces.clear();
  EXPECT_EQ(test::expectInputError([&] { snapToFaceVertices(points_only, {Eigen::Vector3d::Zero()}); }).source(),
            "mesh");
}

}  // namespace
}  // namespace icrkit::icr
