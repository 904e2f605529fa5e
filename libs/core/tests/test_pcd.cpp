#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/pcd.hpp>

#include <liblzf/lzf.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace icrkit::io {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

template <typename T>
void appendRaw(std::string& out, T value) {
  char raw[sizeof value];
  std::memcpy(raw, &value, sizeof value);
  out.append(raw, sizeof value);
}

std::string header(const std::string& fields, const std::string& sizes, const std::string& types,
                   const std::string& counts, std::size_t width, std::size_t height, const std::string& data) {
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes +
         "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " + std::to_string(width) + "\nHEIGHT " +
         std::to_string(height) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(width * height) +
         "\nDATA " + data + "\n";
}

std::string pcdError(const std::string& bytes) {
  try {
    parsePcd(bytes, "test.pcd");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

float floatFromBits(std::uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// The fields of the hand-made test clouds: positions, a packed colour, a
// 3-value histogram (skipped), an unsigned byte and a signed short.
const char* const kFields = "x y z rgb hist label offset";
const char* const kSizes = "4 4 4 4 4 1 2";
const char* const kTypes = "F F F U F U I";
const char* const kCounts = "1 1 1 1 3 1 1";

struct SamplePoint {
  float x, y, z;
  std::uint32_t rgb;
  std::uint8_t label;
  std::int16_t offset;
};
const SamplePoint kSamples[] = {{1.5f, -2.25f, 3.0f, 0xff102030u, 7, -300},
                                {0.1f, 0.2f, 0.3f, 0x00ff0080u, 255, 32767},
                                {std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 1},
                                {-4.0f, 5.0f, 1e-3f, 0x80000001u, 0, -32768}};

void expectSampleCloud(const PointCloud& cloud) {
  // The third sample has a NaN coordinate and is dropped.
  ASSERT_EQ(cloud.size(), 3u);
  const std::size_t kept[] = {0, 1, 3};
  ASSERT_TRUE(cloud.hasColours());
  EXPECT_FALSE(cloud.hasNormals());
  ASSERT_EQ(cloud.attributes.size(), 2u);
  const Attribute& label = cloud.attributes.get("label");
  const Attribute& offset = cloud.attributes.get("offset");
  EXPECT_EQ(label.type, ScalarType::UInt8);
  EXPECT_EQ(offset.type, ScalarType::Int16);
  EXPECT_FALSE(cloud.attributes.has("hist"));
  for (std::size_t i = 0; i < 3; ++i) {
    const SamplePoint& s = kSamples[kept[i]];
    EXPECT_EQ(cloud.positions[i], Eigen::Vector3d(s.x, s.y, s.z)) << i;
    const Colour expected{static_cast<std::uint8_t>(s.rgb >> 16), static_cast<std::uint8_t>(s.rgb >> 8),
                         static_cast<std::uint8_t>(s.rgb)};
    EXPECT_EQ(cloud.colours[i], expected) << i;
    EXPECT_EQ(label.values[i], s.label) << i;
    EXPECT_EQ(offset.values[i], s.offset) << i;
  }
}

TEST(PcdReader, Ascii) {
  std::string text = header(kFields, kSizes, kTypes, kCounts, 2, 2, "ascii");
  for (const SamplePoint& s : kSamples) {
    std::ostringstream line;
    line.precision(9);
    line << s.x << ' ' << s.y << ' ' << s.z << ' ' << s.rgb << " 0.5 1 2e3 " << int(s.label) << ' ' << s.offset
         << "\r\n";
    text += line.str();
  }
  expectSampleCloud(parsePcd(text, "t.pcd"));
}

TEST(PcdReader, AsciiRgbAsPackedFloat) {
  // PCL writes `rgb` of TYPE F as the float whose bits are the packed colour.
  std::ostringstream line;
  line.precision(9);
  line << "1 2 3 " << floatFromBits(0x00abcdefu) << "\n";
  const PointCloud cloud = parsePcd(header("x y z rgb", "4 4 4 4", "F F F F", "1 1 1 1", 1, 1, "ascii") + line.str(),
                                    "t.pcd");
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(cloud.colours[0], (Colour{0xab, 0xcd, 0xef}));
}

std::string sampleBinaryPointMajor() {
  std::string bytes;
  for (const SamplePoint& s : kSamples) {
    appendRaw(bytes, s.x);
    appendRaw(bytes, s.y);
    appendRaw(bytes, s.z);
    appendRaw(bytes, s.rgb);
    for (float h : {0.5f, 1.0f, 2.0f}) appendRaw(bytes, h);
    appendRaw(bytes, s.label);
    appendRaw(bytes, s.offset);
  }
  return bytes;
}

TEST(PcdReader, Binary) {
  const std::string bytes = header(kFields, kSizes, kTypes, kCounts, 2, 2, "binary") + sampleBinaryPointMajor();
  expectSampleCloud(parsePcd(bytes, "t.pcd"));
}

// PCL's binary_compressed payload: each field's values for all points, one
// field after the other, LZF-compressed.
std::string sampleFieldMajor() {
  std::string bytes;
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.x);
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.y);
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.z);
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.rgb);
  for (std::size_t i = 0; i < std::size(kSamples); ++i)
    for (float h : {0.5f, 1.0f, 2.0f}) appendRaw(bytes, h);
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.label);
  for (const SamplePoint& s : kSamples) appendRaw(bytes, s.offset);
  return bytes;
}

std::string compressedPayload(const std::string& raw) {
  std::vector<char> compressed(raw.size() * 2 + 64);
  const unsigned int size = lzf_compress(raw.data(), static_cast<unsigned int>(raw.size()), compressed.data(),
                                         static_cast<unsigned int>(compressed.size()));
  EXPECT_GT(size, 0u);
  std::string out;
  appendRaw(out, static_cast<std::uint32_t>(size));
  appendRaw(out, static_cast<std::uint32_t>(raw.size()));
  out.append(compressed.data(), size);
  return out;
}

TEST(PcdReader, BinaryCompressed) {
  const std::string bytes =
      header(kFields, kSizes, kTypes, kCounts, 2, 2, "binary_compressed") + compressedPayload(sampleFieldMajor());
  expectSampleCloud(parsePcd(bytes, "t.pcd"));
}

TEST(PcdReader, NormalsRgbaAndMissingCountLine) {
  std::string bytes =
      "VERSION .7\nFIELDS x y z normal_x normal_y normal_z rgba curvature\nSIZE 8 8 8 4 4 4 4 4\n"
      "TYPE F F F F F F U F\nWIDTH 1\nPOINTS 1\nDATA binary\n";
  for (double v : {1.0, 2.0, 3.0}) appendRaw(bytes, v);
  for (float v : {0.0f, 0.6f, 0.8f}) appendRaw(bytes, v);
  appendRaw(bytes, std::uint32_t{0x7f010203u});
  appendRaw(bytes, 0.25f);
  const PointCloud cloud = parsePcd(bytes, "t.pcd");
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(cloud.positions[0], Eigen::Vector3d(1, 2, 3));
  ASSERT_TRUE(cloud.hasNormals());
  EXPECT_EQ(cloud.normals[0], Eigen::Vector3d(0.0, double(0.6f), double(0.8f)));
  EXPECT_EQ(cloud.colours[0], (Colour{1, 2, 3}));
  EXPECT_EQ(cloud.attributes.get("curvature").values[0], 0.25);
  EXPECT_EQ(cloud.attributes.get("curvature").type, ScalarType::Float32);
}

TEST(PcdReader, IncompleteNormalsBecomeAttributes) {
  const PointCloud cloud =
      parsePcd(header("x y z normal_x", "4 4 4 4", "F F F F", "1 1 1 1", 1, 1, "ascii") + "1 2 3 0.5\n", "t.pcd");
  EXPECT_FALSE(cloud.hasNormals());
  EXPECT_EQ(cloud.attributes.get("normal_x").values.at(0), 0.5);
}

TEST(PcdReader, EmptyCloud) {
  EXPECT_TRUE(parsePcd(header("x y z", "4 4 4", "F F F", "1 1 1", 0, 1, "ascii"), "t.pcd").empty());
  EXPECT_TRUE(parsePcd(header("x y z", "4 4 4", "F F F", "1 1 1", 0, 1, "binary"), "t.pcd").empty());
  EXPECT_TRUE(parsePcd(header("x y z", "4 4 4", "F F F", "1 1 1", 0, 0, "binary_compressed") +
                           std::string(8, '\0'),
                       "t.pcd")
                  .empty());
}

// ---- errors ----

TEST(PcdReader, HeaderErrorsNameTheLine) {
  const std::string xyz_ascii = header("x y z", "4 4 4", "F F F", "1 1 1", 1, 1, "ascii");
  struct Case {
    std::string bytes;
    std::string location;
    std::string fragment;
  };
  const Case cases[] = {
      {"VERSION 0.7\nFIELDS x y z\n", "line 3", "DATA"},
      {"FIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "line 5", "SIZE has 2"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "line 5", "TYPE has 2"},
      {"FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "line 5", "SIZE 3"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nPOINTS 1\nDATA ascii\n1 2 3\n", "line 5", "TYPE Q"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 0 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "line 6", "COUNT"},
      {"FIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 1\nDATA ascii\n1 2\n", "line 5", "no field 'z'"},
      {"FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 1\nDATA ascii\n1 2 3 4\n", "line 5", "twice"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n", "line 7", "disagrees"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS -1\nDATA ascii\n", "line 4", "POINTS"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA zip\n", "line 5", "zip"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nDATA ascii\n", "line 4", "neither POINTS nor WIDTH"},
      {xyz_ascii + "1 2\n", "line 12", "found 2 values"},
      {xyz_ascii + "1 2 x\n", "line 12", "'x'"},
      {xyz_ascii + "# only a comment here\n", "line", "found 0 data lines"},
      {xyz_ascii + "\n", "line 13", "found 0 data lines"},
      {xyz_ascii + "1 2 3\n4 5 6\n", "line 13", "more data lines"},
      {header("x y z l", "4 4 4 1", "F F F U", "1 1 1 1", 1, 1, "ascii") + "1 2 3 256\n", "line 12", "'256'"},
  };
  for (const Case& c : cases) {
    const std::string message = pcdError(c.bytes);
    EXPECT_NE(message.find("test.pcd:" + c.location), std::string::npos) << c.bytes << " -> " << message;
    EXPECT_NE(message.find(c.fragment), std::string::npos) << c.bytes << " -> " << message;
  }
}

TEST(PcdReader, ClaimsBeyondTheFileAreRejectedWithoutAllocating) {
  const std::string big = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1000000000000\n";
  EXPECT_NE(pcdError(big + "DATA binary\n" + std::string(24, '\0')).find("POINTS"), std::string::npos);
  EXPECT_NE(pcdError(big + "DATA ascii\n1 2 3\n").find("found 1 data lines, expected POINTS 1000000000000"),
            std::string::npos);
  std::string compressed_sizes;
  appendRaw(compressed_sizes, std::uint32_t{100});
  appendRaw(compressed_sizes, std::uint32_t{12});
  EXPECT_NE(pcdError(big + "DATA binary_compressed\n" + compressed_sizes).find("disagrees"), std::string::npos);
  // Huge COUNT: the point size is checked against the data, not allocated.
  EXPECT_NE(pcdError("FIELDS x y z h\nSIZE 4 4 4 8\nTYPE F F F F\nCOUNT 1 1 1 2147483648\nPOINTS 2\nDATA binary\n" +
                     std::string(64, '\0'))
                .find("need more"),
            std::string::npos);

  const std::string small = header("x y z", "4 4 4", "F F F", "1 1 1", 1, 1, "binary_compressed");
  std::string too_long;
  appendRaw(too_long, std::uint32_t{1000});
  appendRaw(too_long, std::uint32_t{12});
  EXPECT_NE(pcdError(small + too_long + "abc").find("exceeds"), std::string::npos);
  std::string wrong_size;
  appendRaw(wrong_size, std::uint32_t{3});
  appendRaw(wrong_size, std::uint32_t{13});
  EXPECT_NE(pcdError(small + wrong_size + "abc").find("disagrees"), std::string::npos);
  std::string expands_too_much;
  appendRaw(expands_too_much, std::uint32_t{0});
  appendRaw(expands_too_much, std::uint32_t{12});
  EXPECT_NE(pcdError(small + expands_too_much).find("cannot come from"), std::string::npos);
  EXPECT_NE(pcdError(small + "1234").find("at least"), std::string::npos);
  EXPECT_NE(pcdError(header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "binary") + std::string(23, '\0'))
                .find("test.pcd:byte "),
            std::string::npos);
}

TEST(PcdReader, CorruptLzfDataIsAnError) {
  std::string payload = compressedPayload(sampleFieldMajor());
  // A back reference to before the start of the output.
  payload[8] = static_cast<char>(0xe0);
  payload[9] = static_cast<char>(0x00);
  payload[10] = static_cast<char>(0xff);
  const std::string message = pcdError(header(kFields, kSizes, kTypes, kCounts, 2, 2, "binary_compressed") + payload);
  EXPECT_NE(message.find("corrupt"), std::string::npos) << message;
}

// Random damage to valid files must give a cloud or an InputError, never a
// crash, a hang or an enormous allocation (run under ASan to see the first).
TEST(PcdReader, SurvivesRandomCorruption) {
  const std::string originals[] = {
      header(kFields, kSizes, kTypes, kCounts, 2, 2, "binary_compressed") + compressedPayload(sampleFieldMajor()),
      header(kFields, kSizes, kTypes, kCounts, 2, 2, "binary") + sampleBinaryPointMajor(),
      header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "ascii") + "1 2 3\n4 5 6\n"};
  std::mt19937 rng(11);
  int parsed = 0;
  for (const std::string& original : originals) {
    for (int trial = 0; trial < 3000; ++trial) {
      std::string bytes = original;
      std::uniform_int_distribution<std::size_t> position(0, bytes.size() - 1);
      const int damage = trial % 4;
      if (damage == 0) {
        bytes[position(rng)] = static_cast<char>(rng());
      } else if (damage == 1) {
        bytes.resize(position(rng));
      } else if (damage == 2) {
        bytes[position(rng)] = static_cast<char>('0' + rng() % 10);
        bytes[position(rng)] = static_cast<char>('0' + rng() % 10);
      } else {
        for (int k = 0; k < 8; ++k) bytes[position(rng)] ^= static_cast<char>(1 << (rng() % 8));
      }
      try {
        const PointCloud cloud = parsePcd(bytes, "fuzz.pcd");
        EXPECT_LE(cloud.size(), original.size());
        ++parsed;
      } catch (const InputError&) {
      }
    }
  }
  EXPECT_GT(parsed, 0);
}

// ---- writing ----

PointCloud randomCloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  std::uniform_int_distribution<int> byte(0, 255);
  PointCloud cloud;
  for (std::size_t i = 0; i < n; ++i) {
    cloud.positions.emplace_back(coordinate(rng), coordinate(rng) * 1e-6, coordinate(rng) * 1e6);
    cloud.normals.push_back(Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng)).normalized());
    cloud.colours.push_back(Colour{static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                                 static_cast<std::uint8_t>(byte(rng))});
  }
  const ScalarType types[] = {ScalarType::Int8,   ScalarType::UInt8,  ScalarType::Int16,   ScalarType::UInt16,
                              ScalarType::Int32,  ScalarType::UInt32, ScalarType::Float32, ScalarType::Float64};
  const char* names[] = {"i8", "excluded", "i16", "u16", "region", "u32", "flatness", "cardinality"};
  for (int t = 0; t < 8; ++t) {
    std::vector<double> values;
    for (std::size_t i = 0; i < n; ++i) values.push_back(representAs(types[t], coordinate(rng) * 1e4));
    if (n > 0) values[0] = representAs(types[t], -1e300);  // clamps to the type's lowest
    cloud.attributes.add(names[t], types[t], std::move(values));
  }
  return cloud;
}

void expectIdentical(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.hasNormals(), b.hasNormals());
  ASSERT_EQ(a.hasColours(), b.hasColours());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.positions[i], b.positions[i]) << i;
    if (a.hasNormals()) {
      EXPECT_EQ(a.normals[i], b.normals[i]) << i;
    }
    if (a.hasColours()) {
      EXPECT_EQ(a.colours[i], b.colours[i]) << i;
    }
  }
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  auto ia = a.attributes.begin();
  auto ib = b.attributes.begin();
  for (; ia != a.attributes.end(); ++ia, ++ib) {
    EXPECT_EQ(ia->name, ib->name);
    EXPECT_EQ(ia->type, ib->type) << ia->name;
    EXPECT_EQ(ia->values, ib->values) << ia->name;
  }
}

TEST(PcdWriter, BinaryRoundTripIsBitIdentical) {
  const PointCloud cloud = randomCloud(1000, 5);
  std::ostringstream out;
  writePcd(out, cloud);
  EXPECT_EQ(out.str().find("DATA binary\n"), out.str().find("DATA"));
  EXPECT_NE(out.str().find("SIZE 8 8 8 8 8 8 4 1 1 2 2 4 4 4 8\n"), std::string::npos) << out.str().substr(0, 300);
  expectIdentical(parsePcd(out.str(), "round.pcd"), cloud);
}

TEST(PcdWriter, AsciiRoundTripIsExact) {
  const PointCloud cloud = randomCloud(500, 6);
  std::ostringstream out;
  WriteOptions options;
  options.encoding = Encoding::Ascii;
  writePcd(out, cloud, options);
  EXPECT_NE(out.str().find("DATA ascii\n"), std::string::npos);
  expectIdentical(parsePcd(out.str(), "round.pcd"), cloud);
}

TEST(PcdWriter, Float32PositionsAreRoundedToFloat) {
  PointCloud cloud = randomCloud(100, 7);
  for (auto encoding : {Encoding::Binary, Encoding::Ascii}) {
    std::ostringstream out;
    WriteOptions options;
    options.encoding = encoding;
    options.real_type = ScalarType::Float32;
    writePcd(out, cloud, options);
    EXPECT_NE(out.str().find("TYPE F F F F F F U"), std::string::npos);
    EXPECT_NE(out.str().find("SIZE 4 4 4 4 4 4 4"), std::string::npos);
    const PointCloud back = parsePcd(out.str(), "round.pcd");
    ASSERT_EQ(back.size(), cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      EXPECT_EQ(back.positions[i], cloud.positions[i].cast<float>().cast<double>()) << i;
      EXPECT_EQ(back.normals[i], cloud.normals[i].cast<float>().cast<double>()) << i;
    }
  }
}

TEST(PcdWriter, MinimalHeader) {
  PointCloud cloud;
  cloud.positions = {Eigen::Vector3d(1, 2, 3)};
  std::ostringstream out;
  WriteOptions options;
  options.encoding = Encoding::Ascii;
  writePcd(out, cloud, options);
  EXPECT_EQ(out.str(),
            "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\n"
            "COUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n");
}

TEST(PcdWriter, RejectsAttributeNamesThatCannotBeFields) {
  PointCloud cloud;
  cloud.positions = {Eigen::Vector3d(1, 2, 3)};
  cloud.attributes.add("two words", ScalarType::Float32, 1);
  std::ostringstream out;
  EXPECT_THROW(writePcd(out, cloud), std::invalid_argument);
  cloud.attributes.remove("two words");
  cloud.attributes.add("rgb", ScalarType::Float32, 1);
  EXPECT_THROW(writePcd(out, cloud), std::invalid_argument);
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

TEST(PcdSharedData, Milk) {
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/pcl-views/milk.pcd";
  std::string bytes;
  if (!readFile(path, bytes)) GTEST_SKIP() << "shared data file missing: " << path;
  const PointCloud cloud = parsePcd(bytes, path);
  EXPECT_EQ(cloud.size(), 13704u);  // every point is finite
  EXPECT_FALSE(cloud.hasColours());
  EXPECT_EQ(cloud.positions[0], Eigen::Vector3d(-0.13160760700702667, -0.2095429003238678, 0.7720000147819519));
  EXPECT_NO_THROW(cloud.validate());
  const Eigen::AlignedBox3d box = cloud.bounds();
  // A milk carton seen from about a metre: decimetre-sized, not garbage.
  EXPECT_LT(box.sizes().maxCoeff(), 1.0);
  EXPECT_GT(box.sizes().minCoeff(), 0.01);
}

TEST(PcdSharedData, TableSceneDropsInvalidPixels) {
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/pcl-views/table_scene_mug_stereo_textured.pcd";
  std::string bytes;
  if (!readFile(path, bytes)) GTEST_SKIP() << "shared data file missing: " << path;
  const auto start = std::chrono::steady_clock::now();
  const PointCloud cloud = parsePcd(bytes, path);
  const double ms = millisecondsSince(start);
  std::cout << "table_scene_mug_stereo_textured.pcd: " << cloud.size() << " finite of 307200 points, parsed in "
            << ms << " ms\n";
  // Counted independently (decompressing in Python): 98,080 pixels are NaN.
  EXPECT_EQ(cloud.size(), 209280u);
  EXPECT_EQ(cloud.positions[0], Eigen::Vector3d(-0.3819099962711334, -0.448199987411499, 2.0257999897003174));
  ASSERT_TRUE(cloud.hasColours());
  EXPECT_NO_THROW(cloud.validate());
  // Writing and reading back keeps every bit.
  std::ostringstream out;
  writePcd(out, cloud);
  expectIdentical(parsePcd(out.str(), "round.pcd"), cloud);
}

}  // namespace
}  // namespace icrkit::io
