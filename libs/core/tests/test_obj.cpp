#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/obj.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace icrkit::io {
namespace {

const char* const kSquare =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n";

std::string objError(const std::string& text) {
  try {
    parseObj(text, "test.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expectFaces(const TriangleMesh& mesh, const std::vector<Triangle>& expected) {
  ASSERT_EQ(mesh.faces.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(mesh.faces[i], expected[i]) << "face " << i;
}

TEST(ObjReader, EveryCornerSyntax) {
  const std::string text = std::string(kSquare) +
                           "vt 0 0\nvt 1 0\nvt 1 1\n"
                           "vn 0 0 1\n"
                           "f 1 2 3\n"
                           "f 1/1 3/3 4/2\n"
                           "f 1//1 2//1 3//1\n"
                           "f 1/1/1 3/2/1 4/3/1\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  EXPECT_EQ(mesh.vertexCount(), 4u);
  expectFaces(mesh, {Triangle(0, 1, 2), Triangle(0, 2, 3), Triangle(0, 1, 2), Triangle(0, 2, 3)});
  ASSERT_TRUE(mesh.vertices.hasNormals());
  for (const Eigen::Vector3d& n : mesh.vertices.normals) EXPECT_EQ(n, Eigen::Vector3d(0, 0, 1));
}

TEST(ObjReader, NegativeIndicesAreRelativeToTheVerticesSoFar) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f -3 -2 -1\n"
      "v 5 5 5\n"
      "vn 1 0 0\nvn 0 1 0\n"
      "f -4//-2 -1//-1 -3//-2\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  expectFaces(mesh, {Triangle(0, 1, 2), Triangle(0, 3, 1)});
  ASSERT_TRUE(mesh.vertices.hasNormals());
  EXPECT_EQ(mesh.vertices.normals[0], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(mesh.vertices.normals[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(mesh.vertices.normals[3], Eigen::Vector3d(0, 1, 0));
  // Vertex 2 is only used by a face without normals.
  EXPECT_EQ(mesh.vertices.normals[2], Eigen::Vector3d::Zero());
}

TEST(ObjReader, PolygonsAreFanTriangulated) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
      "f 1 2 3 4\n"
      "f 1 2 3 4 5\n";
  expectFaces(parseObj(text, "t.obj"), {Triangle(0, 1, 2), Triangle(0, 2, 3), Triangle(0, 1, 2), Triangle(0, 2, 3),
                                        Triangle(0, 3, 4)});
}

TEST(ObjReader, ExtraColumnsAndOtherStatementsAreIgnored) {
  const std::string text =
      "# comment\r\n"
      "mtllib x.mtl\r\n"
      "o thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
      "v 1 2 3 1.0 0.5 0.5 0.5\r\n"
      "v 4 5 6 # trailing comment\r\n"
      "v 7 8 9\r\n"
      "l 1 2\r\np 3\r\n"
      "f 1 2 3 # comment\r\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  ASSERT_EQ(mesh.vertexCount(), 3u);
  EXPECT_EQ(mesh.vertices.positions[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(mesh.vertices.positions[2], Eigen::Vector3d(7, 8, 9));
  expectFaces(mesh, {Triangle(0, 1, 2)});
  EXPECT_FALSE(mesh.vertices.hasNormals());
}

TEST(ObjReader, SingleNormalPerVertexIsKeptAsStored) {
  // Not unit length on purpose: the stored value must come through untouched.
  const std::string text = std::string(kSquare) +
                           "vn 0 0 0.999999\nvn 0.6 0 0.8\n"
                           "f 1//1 2//1 3//2\n"
                           "f 1//1 3//2 4//2\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  EXPECT_EQ(mesh.vertices.normals[0], Eigen::Vector3d(0, 0, 0.999999));
  EXPECT_EQ(mesh.vertices.normals[1], Eigen::Vector3d(0, 0, 0.999999));
  EXPECT_EQ(mesh.vertices.normals[2], Eigen::Vector3d(0.6, 0, 0.8));
  EXPECT_EQ(mesh.vertices.normals[3], Eigen::Vector3d(0.6, 0, 0.8));
}

TEST(ObjReader, DifferentCornerNormalsAreAveraged) {
  // Vertex 1 sits on a cube edge: twice with +x (two triangles of one side),
  // once with +y. Each distinct direction counts once.
  const std::string text = std::string(kSquare) +
                           "vn 1 0 0\nvn 0 1 0\nvn 0 2 0\n"
                           "f 1//1 2//1 3//1\n"
                           "f 1//1 3//1 4//1\n"
                           "f 1//2 4//3 2//2\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  const double h = std::sqrt(0.5);
  EXPECT_NEAR((mesh.vertices.normals[0] - Eigen::Vector3d(h, h, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((mesh.vertices.normals[1] - Eigen::Vector3d(h, h, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(mesh.vertices.normals[2], Eigen::Vector3d(1, 0, 0));
  // Normals 2 and 3 point the same way; their mean is the unit direction.
  EXPECT_NEAR((mesh.vertices.normals[3] - Eigen::Vector3d(h, h, 0)).norm(), 0.0, 1e-15);
}

TEST(ObjReader, DuplicateNormalValuesCountAsOne) {
  const std::string text = std::string(kSquare) +
                           "vn 0 0 1\nvn 0 0 1\n"
                           "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n";
  const TriangleMesh mesh = parseObj(text, "t.obj");
  EXPECT_EQ(mesh.vertices.normals[0], Eigen::Vector3d(0, 0, 1));
}

TEST(ObjReader, NormalsPairedByIndexWhenNoFaceReferencesThem) {
  const TriangleMesh with_faces = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 2\nvn 0 0 3\nf 1 2 3\n", "t");
  ASSERT_TRUE(with_faces.vertices.hasNormals());
  EXPECT_EQ(with_faces.vertices.normals[2], Eigen::Vector3d(0, 0, 3));
  const TriangleMesh points = parseObj("v 0 0 0\nvn 1 0 0\n", "t");
  ASSERT_TRUE(points.vertices.hasNormals());
  EXPECT_TRUE(points.faces.empty());
  // A count mismatch gives no basis for pairing.
  EXPECT_FALSE(parseObj("v 0 0 0\nv 1 1 1\nvn 1 0 0\n", "t").vertices.hasNormals());
}

TEST(ObjReader, ErrorsNameTheLine) {
  struct Case {
    std::string text;
    std::string location;
    std::string fragment;
  };
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const Case cases[] = {
      {"v 0 0 0\nv 1 x 0\n", "line 2", "'x'"},
      {"v 0 0\n", "line 1", "expected 3"},
      {"# c\nv nan 0 0\n", "line 2", "finite"},
      {"v 0 inf 0\n", "line 1", "finite"},
      {"vn 0 0 1e400\n", "line 1", "finite"},
      {v3 + "f 1 2 0\n", "line 4", "vertex 0"},
      {v3 + "f 1 2 4\n", "line 4", "vertex 4"},
      {v3 + "f 1 2 -4\n", "line 4", "vertex -4"},
      {v3 + "f 1 2\n", "line 4", "2 corners"},
      {v3 + "f\n", "line 4", "0 corners"},
      {v3 + "f 1 2 a\n", "line 4", "'a'"},
      {v3 + "f 1//1 2//1 3//1\n", "line 4", "normal 1"},
      {v3 + "vn 0 0 1\nf 1//1 2//2 3//1\n", "line 5", "normal 2"},
      {v3 + "f 1/1 2/1 3/1\n", "line 4", "texture coordinate 1"},
      {v3 + "vn 0 0 1\nf 1/ 2 3\n", "line 5", "empty texture"},
      {v3 + "vn 0 0 1\nf 1// 2 3\n", "line 5", "malformed"},
      {v3 + "vn 0 0 1\nf 1//1/1 2 3\n", "line 5", "malformed"},
      {v3 + "f 1 2 99999999999999999999\n", "line 4", "vertex index"},
  };
  for (const Case& c : cases) {
    const std::string message = objError(c.text);
    EXPECT_NE(message.find("test.obj:" + c.location + ":"), std::string::npos) << c.text << " -> " << message;
    EXPECT_NE(message.find(c.fragment), std::string::npos) << c.text << " -> " << message;
  }
}

TEST(ObjWriter, WritesOneBasedFacesAndNormals) {
  PointCloud vertices;
  vertices.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0.1, 0)};
  std::ostringstream plain;
  writeObj(plain, vertices, {Triangle(0, 1, 2)});
  EXPECT_EQ(plain.str(), "v 0 0 0\nv 1 0 0\nv 0 0.1 0\nf 1 2 3\n");
  vertices.normals.assign(3, Eigen::Vector3d(0, 0, 1));
  std::ostringstream with_normals;
  writeObj(with_normals, vertices, {Triangle(2, 1, 0)});
  EXPECT_EQ(with_normals.str(),
            "v 0 0 0\nv 1 0 0\nv 0 0.1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 3//3 2//2 1//1\n");
}

TEST(ObjWriter, RejectsFacesOutsideTheVertices) {
  PointCloud vertices;
  vertices.positions.assign(3, Eigen::Vector3d::Zero());
  std::ostringstream out;
  EXPECT_THROW(writeObj(out, vertices, {Triangle(0, 1, 3)}), std::invalid_argument);
  EXPECT_THROW(writeObj(out, vertices, {Triangle(-1, 1, 2)}), std::invalid_argument);
}

TEST(ObjWriter, RoundTripIsExact) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
  TriangleMesh mesh;
  for (int i = 0; i < 300; ++i) {
    mesh.vertices.positions.emplace_back(coordinate(rng), coordinate(rng) * 1e-7, coordinate(rng) * 1e9);
    mesh.vertices.normals.push_back(Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng)).normalized());
  }
  std::uniform_int_distribution<int> index(0, 299);
  for (int f = 0; f < 500; ++f) mesh.faces.emplace_back(index(rng), index(rng), index(rng));
  std::ostringstream out;
  writeObj(out, mesh.vertices, mesh.faces);
  const TriangleMesh back = parseObj(out.str(), "round.obj");
  ASSERT_EQ(back.vertexCount(), mesh.vertexCount());
  ASSERT_EQ(back.faces, mesh.faces);
  ASSERT_TRUE(back.vertices.hasNormals());
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
    EXPECT_EQ(back.vertices.positions[i], mesh.vertices.positions[i]) << i;
    EXPECT_EQ(back.vertices.normals[i], mesh.vertices.normals[i]) << i;
  }
}

// ---- real data ----

bool readFile(const std::string& path, std::string& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  bytes = buffer.str();
  return true;
}

struct ModelCounts {
  const char* name;
  std::size_t vertices;
  std::size_t faces;
};

class IcrModels : public ::testing::TestWithParam<ModelCounts> {};

TEST_P(IcrModels, LoadsWithTheExpectedCounts) {
  const ModelCounts& model = GetParam();
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/" + model.name + ".obj";
  std::string bytes;
  if (!readFile(path, bytes)) GTEST_SKIP() << "shared data file missing: " << path;
  const TriangleMesh mesh = parseObj(bytes, path);
  EXPECT_EQ(mesh.vertexCount(), model.vertices);
  EXPECT_EQ(mesh.faceCount(), model.faces);
  ASSERT_TRUE(mesh.vertices.hasNormals());
  EXPECT_NO_THROW(mesh.validate());
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i)
    EXPECT_NEAR(mesh.vertices.normals[i].norm(), 1.0, 1e-4) << model.name << " vertex " << i;
}

INSTANTIATE_TEST_SUITE_P(SharedData, IcrModels,
                         ::testing::Values(ModelCounts{"CokePlasticSmall_5k", 2500, 5000},
                                           ModelCounts{"Fish_5k", 2502, 5000}, ModelCounts{"RedCup_5k", 2500, 5000},
                                           ModelCounts{"ShowerGel_5k", 2502, 5000},
                                           ModelCounts{"Sprayflask_5k", 2512, 4999},
                                           ModelCounts{"Tortoise_5k", 2505, 4981},
                                           ModelCounts{"beer_can", 6658, 13312}, ModelCounts{"cup", 2911, 5822},
                                           ModelCounts{"rubik_cube", 6004, 12004},
                                           ModelCounts{"sphere", 1178, 2352}),
                         [](const ::testing::TestParamInfo<ModelCounts>& info) { return std::string(info.param.name); });

TEST(ObjSharedData, RubikCubeTakesNormalsThroughTheirOwnIndices) {
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/rubik_cube.obj";
  std::string bytes;
  if (!readFile(path, bytes)) GTEST_SKIP() << "shared data file missing: " << path;
  const TriangleMesh mesh = parseObj(bytes, path);
  // The first face is "f 320//276 328//284 3//2": vertex 320 is paired with
  // normal 276, not with normal 320.
  EXPECT_EQ(mesh.faces[0], Triangle(319, 327, 2));
  EXPECT_EQ(mesh.vertices.positions[319], Eigen::Vector3d(-7.388889, 27.5, -9.5));
  EXPECT_EQ(mesh.vertices.normals[319], Eigen::Vector3d(-0.064358, -0.997927, 0.0));
}

TEST(ObjSharedData, ParseTimeOfTheLargestModel) {
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/beer_can.obj";
  std::string bytes;
  if (!readFile(path, bytes)) GTEST_SKIP() << "shared data file missing: " << path;
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = parseObj(bytes, path);
  const double ms = millisecondsSince(start);
  RecordProperty("parse_ms", std::to_string(ms));
  std::cout << "beer_can.obj (" << bytes.size() << " bytes) parsed in " << ms << " ms\n";
  EXPECT_EQ(mesh.vertexCount(), 6658u);
}

}  // namespace
}  // namespace icrkit::io
