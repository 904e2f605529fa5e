#include <icrkit/core/error.hpp>
#include <icrkit/core/io/xyz.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

namespace icrkit::io {
namespace {

// The message of the InputError that parsing `text` throws ("" when none).
std::string xyzError(const std::string& text) {
  try {
    parseXyz(text, "test.xyz");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(XyzReader, ThreeColumnsWithCommentsBlankLinesAndCrlf) {
  const PointCloud cloud = parseXyz("# header\r\n\r\n1 2 3\r\n  -4.5\t5e-1 +6 # trailing\n\n7 8 9", "t.xyz");
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_FALSE(cloud.hasNormals());
  EXPECT_EQ(cloud.positions[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(cloud.positions[1], Eigen::Vector3d(-4.5, 0.5, 6));
  EXPECT_EQ(cloud.positions[2], Eigen::Vector3d(7, 8, 9));
}

TEST(XyzReader, SixColumnsGiveNormals) {
  const PointCloud cloud = parseXyz("0 0 0 0 0 1\n1 1 1 1 0 0\n", "t.xyz");
  ASSERT_EQ(cloud.size(), 2u);
  ASSERT_TRUE(cloud.hasNormals());
  EXPECT_EQ(cloud.normals[0], Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(cloud.normals[1], Eigen::Vector3d(1, 0, 0));
}

TEST(XyzReader, EmptyAndCommentOnlyTextsGiveEmptyClouds) {
  EXPECT_TRUE(parseXyz("", "t.xyz").empty());
  EXPECT_TRUE(parseXyz("# nothing\n\n   \n", "t.xyz").empty());
}

TEST(XyzReader, BadNumberNamesTheLine) {
  const std::string message = xyzError("1 2 3\n# c\n4 five 6\n");
  EXPECT_NE(message.find("test.xyz:line 3"), std::string::npos) << message;
  EXPECT_NE(message.find("five"), std::string::npos) << message;
}

TEST(XyzReader, WrongColumnCountNamesTheLine) {
  EXPECT_NE(xyzError("1 2\n").find("line 1"), std::string::npos);
  EXPECT_NE(xyzError("1 2 3 4 5\n").find("line 1"), std::string::npos);
  EXPECT_NE(xyzError("1 2 3 4 5 6 7\n").find("line 1"), std::string::npos);
  const std::string mixed = xyzError("1 2 3\n4 5 6\n1 2 3 0 0 1\n");
  EXPECT_NE(mixed.find("line 3"), std::string::npos) << mixed;
  EXPECT_NE(mixed.find("expected 3"), std::string::npos) << mixed;
}

TEST(XyzReader, NonFiniteValuesAreErrors) {
  EXPECT_NE(xyzError("1 2 3\nnan 0 0\n").find("line 2"), std::string::npos);
  EXPECT_NE(xyzError("1 inf 3\n").find("line 1"), std::string::npos);
  EXPECT_NE(xyzError("1 2 1e999\n").find("line 1"), std::string::npos);
  EXPECT_NE(xyzError("0 0 0 0 0 -inf\n").find("line 1"), std::string::npos);
}

TEST(XyzReader, RoundTripIsExact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1e3, 1e3);
  PointCloud cloud;
  for (int i = 0; i < 500; ++i) {
    cloud.positions.emplace_back(coordinate(rng), coordinate(rng) * 1e-9, coordinate(rng) * 1e12);
    cloud.normals.push_back(Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng)).normalized());
  }
  cloud.positions.emplace_back(std::numeric_limits<double>::denorm_min(), -0.0, std::numeric_limits<double>::max());
  cloud.normals.emplace_back(0, 0, 1);
  std::ostringstream out;
  writeXyz(out, cloud);
  const PointCloud back = parseXyz(out.str(), "round.xyz");
  ASSERT_EQ(back.size(), cloud.size());
  ASSERT_TRUE(back.hasNormals());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(back.positions[i], cloud.positions[i]) << i;
    EXPECT_EQ(back.normals[i], cloud.normals[i]) << i;
  }
  EXPECT_TRUE(std::signbit(back.positions.back().y()));
}

TEST(XyzWriter, WritesThreeColumnsWithoutNormals) {
  PointCloud cloud;
  cloud.positions = {Eigen::Vector3d(0.1, 2, -3.25)};
  std::ostringstream out;
  writeXyz(out, cloud);
  EXPECT_EQ(out.str(), "0.1 2 -3.25\n");
}

}  // namespace
}  // namespace icrkit::io
