#include <icrkit/core/attributes.hpp>
#include <icrkit/core/point_cloud.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace icrkit;

TEST(Attributes, ReferencesSurviveLaterAdds) {
  AttributeSet set;
  Attribute& first = set.add("cardinality", ScalarType::Int32, 3, 1.0);
  for (int i = 0; i < 100; ++i) set.add("a" + std::to_string(i), ScalarType::Float32, 3);
  first.values[2] = 42;
  EXPECT_EQ(set.get("cardinality").values[2], 42.0);
  EXPECT_EQ(set.size(), 101u);
  EXPECT_EQ(set.begin()->name, "cardinality");  // insertion order kept
  EXPECT_THROW(set.get("missing"), std::out_of_range);
  EXPECT_TRUE(set.remove("a5"));
  EXPECT_FALSE(set.has("a5"));
}

TEST(Attributes, RepresentAsRoundsAndClampsToTheType) {
  EXPECT_EQ(representAs(ScalarType::UInt8, 300.0), 255.0);
  EXPECT_EQ(representAs(ScalarType::Int8, -1000.0), -128.0);
  EXPECT_EQ(representAs(ScalarType::Int32, 2.6), 3.0);
  EXPECT_EQ(representAs(ScalarType::UInt16, std::nan("")), 0.0);
  EXPECT_EQ(representAs(ScalarType::Float32, 0.1), static_cast<double>(0.1f));
  EXPECT_EQ(representAs(ScalarType::Float64, 0.1), 0.1);
}

TEST(PointCloud, FlagsSelectAndAppend) {
  PointCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_FALSE(c.flag("excluded", 1));
  c.setFlag("excluded", 1, true);
  EXPECT_TRUE(c.flag("excluded", 1));
  EXPECT_EQ(c.attributes.get("excluded").type, ScalarType::UInt8);
  c.select({2, 1});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[0].x(), 2.0);
  EXPECT_TRUE(c.flag("excluded", 1));
  PointCloud d = c;
  c.append(d);
  EXPECT_EQ(c.size(), 4u);
  EXPECT_TRUE(c.flag("excluded", 3));
  d.normals.assign(2, Eigen::Vector3d::UnitZ());
  EXPECT_THROW(c.append(d), std::invalid_argument);
  c.positions[0].x() = std::nan("");
  EXPECT_THROW(c.validate(), std::invalid_argument);
}
