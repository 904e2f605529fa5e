#include <icrkit/core/error.hpp>
#include <icrkit/core/io/ply.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <sstream>

using namespace icrkit;

namespace {

std::string errorOf(std::string_view bytes) {
  try {
    io::parsePly(bytes, "test.ply");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kAsciiHeader =
    "ply\nformat ascii 1.0\ncomment a comment\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nproperty uchar excluded\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

PointCloud makeCloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.positions.emplace_back(u(rng), u(rng), u(rng));
    c.normals.push_back(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized());
    c.colours.push_back(Colour{static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(2 * i), 7});
  }
  auto& card = c.attributes.add("cardinality", ScalarType::Int32, n);
  auto& excl = c.attributes.add("excluded", ScalarType::UInt8, n);
  auto& flat = c.attributes.add("flatness", ScalarType::Float32, n);
  auto& disp = c.attributes.add("displacement", ScalarType::Float64, n);
  auto& sh = c.attributes.add("s16", ScalarType::Int16, n);
  for (std::size_t i = 0; i < n; ++i) {
    card.values[i] = static_cast<double>(i) - 5;
    excl.values[i] = i % 2;
    flat.values[i] = static_cast<float>(u(rng));
    disp.values[i] = u(rng) * 1e-3;
    sh.values[i] = -static_cast<double>(i);
  }
  return c;
}

}  // namespace

TEST(Ply, ReadsAsciiWithAttributesAndQuads) {
  std::string text = std::string(kAsciiHeader) + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n4 0 1 2 3\n";
  TriangleMesh m = io::parsePly(text, "test.ply");
  ASSERT_EQ(m.vertexCount(), 4u);
  ASSERT_EQ(m.faceCount(), 2u);  // the quad is fan-triangulated
  EXPECT_EQ(m.faces[0], Triangle(0, 1, 2));
  EXPECT_EQ(m.faces[1], Triangle(0, 2, 3));
  EXPECT_EQ(m.vertices.positions[2], Eigen::Vector3d(1, 1, 0));
  ASSERT_TRUE(m.vertices.attributes.has("excluded"));
  EXPECT_EQ(m.vertices.attributes.get("excluded").type, ScalarType::UInt8);
  EXPECT_TRUE(m.vertices.flag("excluded", 0));
  EXPECT_FALSE(m.vertices.flag("excluded", 1));
}

TEST(Ply, ReadsCrlfLineEnds) {
  std::string text = std::string(kAsciiHeader) + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 2\n";
  std::string crlf;
  for (char c : text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  TriangleMesh m = io::parsePly(crlf, "crlf.ply");
  EXPECT_EQ(m.vertexCount(), 4u);
  EXPECT_EQ(m.faceCount(), 1u);
}

TEST(Ply, SkipsUnknownElementsLikeRangeGrid) {
  const std::string text =
      "ply\nformat ascii 1.0\nobj_info num_cols 2\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement range_grid 4\nproperty list uchar int vertex_indices\nend_header\n"
      "1 2 3\n4 5 6\n1 0\n0\n1 1\n0\n";
  TriangleMesh m = io::parsePly(text, "grid.ply");
  EXPECT_EQ(m.vertexCount(), 2u);
  EXPECT_EQ(m.faceCount(), 0u);
  EXPECT_EQ(m.vertices.positions[1], Eigen::Vector3d(4, 5, 6));
}

TEST(Ply, ReadsBinaryBigEndianWrittenByHand) {
  std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\nproperty float y\n"
      "property short z\nend_header\n";
  std::string body;
  auto putBig = [&](const void* p, std::size_t n) {
    const char* bytes = static_cast<const char*>(p);
    for (std::size_t i = 0; i < n; ++i) body += bytes[n - 1 - i];
  };
  double x = 1.25;
  float y = -2.5f;
  std::int16_t z = -300;
  putBig(&x, 8);
  putBig(&y, 4);
  putBig(&z, 2);
  TriangleMesh m = io::parsePly(header + body, "be.ply");
  ASSERT_EQ(m.vertexCount(), 1u);
  EXPECT_EQ(m.vertices.positions[0], Eigen::Vector3d(1.25, -2.5, -300));
}

class PlyRoundTrip : public ::testing::TestWithParam<int> {};

TEST_P(PlyRoundTrip, PreservesEverything) {
  io::WriteOptions options;
  options.encoding = GetParam() == 2 ? io::Encoding::Ascii : io::Encoding::Binary;
  options.big_endian = GetParam() == 1;
  TriangleMesh mesh;
  mesh.vertices = makeCloud(50, 7);
  for (int i = 0; i + 2 < 50; i += 3) mesh.faces.emplace_back(i, i + 1, i + 2);
  std::ostringstream out;
  io::writePly(out, mesh.vertices, mesh.faces, options);
  TriangleMesh back = io::parsePly(out.str(), "roundtrip.ply");
  ASSERT_EQ(back.vertexCount(), mesh.vertexCount());
  EXPECT_EQ(back.faces, mesh.faces);
  EXPECT_EQ(back.vertices.positions, mesh.vertices.positions);  // bit-exact, also in ASCII (shortest round-trip)
  EXPECT_EQ(back.vertices.normals, mesh.vertices.normals);
  EXPECT_EQ(back.vertices.colours, mesh.vertices.colours);
  ASSERT_EQ(back.vertices.attributes.size(), mesh.vertices.attributes.size());
  for (const Attribute& a : mesh.vertices.attributes) {
    const Attribute& b = back.vertices.attributes.get(a.name);
    EXPECT_EQ(b.type, a.type) << a.name;
    for (std::size_t i = 0; i < a.values.size(); ++i)
      EXPECT_EQ(b.values[i], representAs(a.type, a.values[i])) << a.name << " " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, PlyRoundTrip, ::testing::Values(0, 1, 2));

TEST(Ply, SinglePrecisionWritesFloats) {
  PointCloud c = makeCloud(5, 3);
  io::WriteOptions options;
  options.real_type = ScalarType::Float32;
  std::ostringstream out;
  io::writePly(out, c, {}, options);
  EXPECT_NE(out.str().find("property float x"), std::string::npos);
  TriangleMesh back = io::parsePly(out.str(), "f.ply");
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_EQ(back.vertices.positions[i], c.positions[i].cast<float>().cast<double>());
}

TEST(Ply, ErrorsNameTheFileTheLineAndTheExpectation) {
  const std::string header = kAsciiHeader;
  // truncated
  std::string e = errorOf(header + "0 0 0 1\n1 0 0 0\n");
  EXPECT_NE(e.find("test.ply:line 4"), std::string::npos) << e;  // the element's header line
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  // truncated inside the last item: named by its line and item
  e = errorOf(header + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1");
  EXPECT_NE(e.find("line 16"), std::string::npos) << e;
  EXPECT_NE(e.find("face 0"), std::string::npos) << e;
  EXPECT_NE(e.find("end of file"), std::string::npos) << e;
  // bad number, line 14 is the third vertex
  e = errorOf(header + "0 0 0 1\n1 0 0 0\n1 abc 0 1\n0 1 0 0\n3 0 1 2\n");
  EXPECT_NE(e.find("line 14"), std::string::npos) << e;
  EXPECT_NE(e.find("'abc'"), std::string::npos) << e;
  // integer property given a fraction, and a uchar out of range
  e = errorOf(header + "0 0 0 1.5\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 2\n");
  EXPECT_NE(e.find("uchar"), std::string::npos) << e;
  e = errorOf(header + "0 0 0 256\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 2\n");
  EXPECT_NE(e.find("uchar"), std::string::npos) << e;
  // index out of range
  e = errorOf(header + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 4\n");
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;
  EXPECT_NE(e.find("face 0"), std::string::npos) << e;
  // NaN coordinate
  e = errorOf(header + "0 nan 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 2\n");
  EXPECT_NE(e.find("non-finite"), std::string::npos) << e;
  EXPECT_NE(e.find("vertex 0"), std::string::npos) << e;
  // more data than declared
  e = errorOf(header + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 0\n3 0 1 2\n3 0 1 2\n");
  EXPECT_NE(e.find("more data"), std::string::npos) << e;
  // header problems
  EXPECT_NE(errorOf("plx\n").find("not a PLY"), std::string::npos);
  EXPECT_NE(errorOf("ply\nelement vertex 1\nproperty float x\nend_header\n").find("format"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n").find("unknown property type"),
            std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n").find("end_header"), std::string::npos);
  EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n").find("x, y and z"),
            std::string::npos);
}

TEST(Ply, RejectsCountsLargerThanTheFileBeforeAllocating) {
  const std::string text =
      "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const std::string e = errorOf(text + std::string(24, '\0'));
  EXPECT_NE(e.find("line 3"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated or the count is wrong"), std::string::npos) << e;
}

TEST(Ply, BinaryTruncationNamesTheElement) {
  PointCloud c = makeCloud(10, 1);
  std::ostringstream out;
  io::writePly(out, c, {}, {});
  std::string bytes = out.str();
  bytes.resize(bytes.size() - 20);
  std::string e = errorOf(bytes);
  EXPECT_NE(e.find("10 vertex items"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  // A list that runs past the end is named by its element item.
  TriangleMesh m;
  m.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {Triangle(0, 1, 2), Triangle(0, 2, 1)};
  std::ostringstream out2;
  io::writePly(out2, m.vertices, m.faces, {});
  bytes = out2.str();
  bytes.resize(bytes.size() - 2);
  e = errorOf(bytes);
  EXPECT_NE(e.find("face 1"), std::string::npos) << e;
  EXPECT_NE(e.find("end of file"), std::string::npos) << e;
}

TEST(Ply, RealStanfordScanWithRangeGrid) {
  const std::string path = test::sharedData("stanford-bunny/bun000.ply");
  ICRKIT_REQUIRE_SHARED_FILE(path);
  TriangleMesh m = io::readTriangleMesh(path);
  EXPECT_EQ(m.vertexCount(), 40256u);
  EXPECT_EQ(m.faceCount(), 0u);
  EXPECT_NEAR(m.vertices.positions[0].x(), -0.06325, 1e-7);
}

TEST(Ply, RealZipperedBunnyKeepsExtraProperties) {
  const std::string path = test::sharedData("stanford-bunny/bun_zipper.ply");
  ICRKIT_REQUIRE_SHARED_FILE(path);
  TriangleMesh m = io::readTriangleMesh(path);
  EXPECT_EQ(m.vertexCount(), 35947u);
  EXPECT_EQ(m.faceCount(), 69451u);
  EXPECT_TRUE(m.vertices.attributes.has("confidence"));
  EXPECT_TRUE(m.vertices.attributes.has("intensity"));
  // first vertex line: -0.0378297 0.12794 0.00447467 0.850855 0.5
  EXPECT_EQ(m.vertices.attributes.get("confidence").values[0], static_cast<double>(0.850855f));
  EXPECT_EQ(m.vertices.attributes.get("intensity").values[0], 0.5);
  EXPECT_EQ(m.vertices.positions[0].y(), static_cast<double>(0.12794f));
  EXPECT_NO_THROW(m.validate());
}
