#include <icrkit/core/error.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/icr/regions_file.hpp>

#include "test_meshes.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace icrkit;
using namespace icrkit::icr;

namespace {

std::string messageOf(const std::string& text, const TriangleMesh& mesh) {
  try {
    parseRegionsJson(text, "regions.json", mesh, "mesh.ply");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST(RegionsFile, RegionsOfAGraspRoundTrip) {
  const TriangleMesh mesh = test::cubeSphere(8);
  const GraspableObject object = GraspableObject::withDefaultFrame(mesh);
  std::vector<int> contacts;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {1, -1}) contacts.push_back(test::nearestVertex(mesh, sign * Eigen::Vector3d::Unit(axis)));
  const IcrResult result = computeIndependentContactRegions(object, contacts);
  ASSERT_EQ(result.regions.size(), contacts.size());

  const std::string text = regionsJson(result.regions);
  EXPECT_EQ(regionsJson(result.regions), text) << "the same regions give the same bytes";
  const std::vector<StoredRegion> back = parseRegionsJson("{\"regions\": " + text + "}", "regions.json", mesh, "mesh.ply");
  ASSERT_EQ(back.size(), result.regions.size());
  for (std::size_t r = 0; r < back.size(); ++r) {
    EXPECT_EQ(back[r].finger, static_cast<int>(result.regions[r].finger));
    EXPECT_EQ(back[r].contact, result.regions[r].contact);
    EXPECT_EQ(back[r].vertices, result.regions[r].vertices);
    EXPECT_FALSE(back[r].vertices.empty());
  }
}

TEST(RegionsFile, FingerAndContactDefault) {
  const TriangleMesh mesh = test::cubeSphere(4);
  const auto back = parseRegionsJson(R"({"regions": [{"vertices": [0, 1]}, {"vertices": []}]})", "r.json", mesh, "m");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].finger, 0);
  EXPECT_EQ(back[1].finger, 1);
  EXPECT_EQ(back[0].contact, -1);
  EXPECT_EQ(back[0].vertices, (std::vector<int>{0, 1}));
}

TEST(RegionsFile, BadFilesNameTheFileTheEntryAndWhatWasExpected) {
  TriangleMesh mesh = test::cubeSphere(4);
  const std::string out_of_range = std::to_string(mesh.vertexCount());
  EXPECT_NE(messageOf("{", mesh).find("regions.json: is not valid JSON"), std::string::npos) << messageOf("{", mesh);
  EXPECT_NE(messageOf("{\"grasps\": []}", mesh).find("has no \"regions\" array"), std::string::npos);
  EXPECT_NE(messageOf("{\"regions\": [3]}", mesh).find("regions[0]"), std::string::npos);
  const std::string range = messageOf("{\"regions\": [{\"finger\": 2, \"vertices\": [0, " + out_of_range + "]}]}", mesh);
  EXPECT_NE(range.find("regions[0] (finger 2).vertices[1]"), std::string::npos) << range;
  EXPECT_NE(range.find("out of range for mesh.ply"), std::string::npos) << range;
  EXPECT_NE(messageOf(R"({"regions": [{"finger": 1, "vertices": []}, {"finger": 1, "vertices": []}]})", mesh)
                .find("finger 1 has more than one region"),
            std::string::npos);
  EXPECT_NE(messageOf(R"({"regions": [{"finger": -1, "vertices": []}]})", mesh).find("finger index"), std::string::npos);
  EXPECT_NE(messageOf(R"({"regions": [{"vertices": [0.5]}]})", mesh).find("expected a vertex index"), std::string::npos);
  // A vertex no face uses cannot be in a region.
  mesh.vertices.positions.push_back(Eigen::Vector3d(5, 5, 5));
  mesh.vertices.normals.push_back(Eigen::Vector3d::UnitZ());
  const std::string loose = messageOf("{\"regions\": [{\"vertices\": [" + out_of_range + "]}]}", mesh);
  EXPECT_NE(loose.find("is used by no face of mesh.ply"), std::string::npos) << loose;
}

TEST(RegionsFile, AMissingFileIsAnInputError) {
  const TriangleMesh mesh = test::cubeSphere(4);
  EXPECT_THROW(readRegionsFile("/nonexistent/regions.json", mesh, "m"), InputError);
}
