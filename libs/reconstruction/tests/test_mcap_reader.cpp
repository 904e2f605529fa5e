/// \file
/// ROS 2 bags (MCAP): CDR decoding of hand-built buffers, CRC-32, and small
/// bags written here record by record (a writer independent of the reader's
/// code paths) to check image order, pose interpolation, tf chains,
/// compressed chunks and the errors that name the topic or the record.

#include "simulated_recordings.hpp"

#include "input/mcap/cdr_reader.hpp"
#include "input/mcap/mcap_records.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/reconstruction/input/depth_image_scan.hpp>
#include <icrkit/reconstruction/input/mcap_reader.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>

#include <icrkit/reconstruction/reconstruction_outputs.hpp>

#include <gtest/gtest.h>
#include <lz4frame.h>
#include <zstd.h>

#include <test_support.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace icrkit::reconstruction {
namespace {

using Bytes = std::vector<std::uint8_t>;
using test::expectInputError;
using testing_support::scratchFolder;

void putLittle(Bytes& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

// CDR as ROS 2 writes it, little or big endian.
class CdrWriter {
 public:
  explicit CdrWriter(bool little = true) : little_(little) { out_ = {0x00, static_cast<std::uint8_t>(little ? 1 : 0), 0, 0}; }
  CdrWriter& u8(std::uint8_t v) { return put(v, 1); }
  CdrWriter& u16(std::uint16_t v) { return put(v, 2); }
  CdrWriter& u32(std::uint32_t v) { return put(v, 4); }
  CdrWriter& i32(std::int32_t v) { return put(static_cast<std::uint32_t>(v), 4); }
  CdrWriter& f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    return put(bits, 8);
  }
  CdrWriter& str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size() + 1));
    out_.insert(out_.end(), s.begin(), s.end());
    out_.push_back(0);
    return *this;
  }
  CdrWriter& raw(const Bytes& b) {
    out_.insert(out_.end(), b.begin(), b.end());
    return *this;
  }
  CdrWriter& header(double stamp, const std::string& frame) {
    const auto sec = static_cast<std::int32_t>(std::floor(stamp));
    i32(sec);
    u32(static_cast<std::uint32_t>(std::llround((stamp - sec) * 1e9)));
    return str(frame);
  }
  const Bytes& bytes() const { return out_; }

 private:
  CdrWriter& put(std::uint64_t v, int n) {
    while ((out_.size() - 4) % static_cast<std::size_t>(n) != 0) out_.push_back(0);
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * (little_ ? i : n - 1 - i))));
    return *this;
  }
  bool little_;
  Bytes out_;
};

Bytes imageMessage(double stamp, int width, int height, const std::vector<std::uint16_t>& counts,
                   const std::string& encoding = "16UC1", const std::string& frame = "cam") {
  CdrWriter w;
  w.header(stamp, frame).u32(static_cast<std::uint32_t>(height)).u32(static_cast<std::uint32_t>(width)).str(encoding);
  w.u8(0).u32(static_cast<std::uint32_t>(width * 2)).u32(static_cast<std::uint32_t>(counts.size() * 2));
  Bytes data;
  for (std::uint16_t c : counts) putLittle(data, c, 2);
  return w.raw(data).bytes();
}

Bytes cameraInfoMessage(int width, int height, double fx, double fy, double cx, double cy) {
  CdrWriter w;
  w.header(0, "cam").u32(static_cast<std::uint32_t>(height)).u32(static_cast<std::uint32_t>(width)).str("plumb_bob");
  w.u32(5);
  for (int i = 0; i < 5; ++i) w.f64(0.0);
  for (double v : {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}) w.f64(v);
  for (int i = 0; i < 9 + 12; ++i) w.f64(0.0);
  w.u32(0).u32(0).u32(0).u32(0).u32(0).u32(0).u8(0);
  return w.bytes();
}

void putTransform(CdrWriter& w, const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  w.f64(t.x()).f64(t.y()).f64(t.z()).f64(q.x()).f64(q.y()).f64(q.z()).f64(q.w());
}

Bytes poseMessage(double stamp, const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  CdrWriter w;
  w.header(stamp, "world");
  putTransform(w, t, q);
  return w.bytes();
}

struct TfEdge {
  double stamp;
  std::string parent, child;
  Eigen::Vector3d t;
  Eigen::Quaterniond q;
};
Bytes tfMessage(const std::vector<TfEdge>& edges) {
  CdrWriter w;
  w.u32(static_cast<std::uint32_t>(edges.size()));
  for (const TfEdge& e : edges) {
    w.header(e.stamp, e.parent).str(e.child);
    putTransform(w, e.t, e.q);
  }
  return w.bytes();
}

// A bag written record by record: schemas and channels at the top level,
// messages into chunks (or at the top level), as the spec lays them out.
class TestBag {
 public:
  TestBag() {
    file_.assign(std::begin(mcap::kMagic), std::end(mcap::kMagic));
    Bytes header;
    putString(header, "ros2");
    putString(header, "icrkit test");
    record(file_, 0x01, header);
  }
  void channel(const std::string& topic, const std::string& schema) {
    const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
    Bytes s;
    putLittle(s, id, 2);
    putString(s, schema);
    putString(s, "ros2msg");
    putLittle(s, 0, 4);
    record(file_, 0x03, s);
    Bytes c;
    putLittle(c, id, 2);
    putLittle(c, id, 2);
    putString(c, topic);
    putString(c, "cdr");
    putLittle(c, 0, 4);
    record(file_, 0x04, c);
    channels_[topic] = id;
  }
  void message(const std::string& topic, const Bytes& data, bool top_level = false) {
    Bytes m;
    putLittle(m, channels_.at(topic), 2);
    putLittle(m, 0, 4);
    putLittle(m, 0, 8);
    putLittle(m, 0, 8);
    m.insert(m.end(), data.begin(), data.end());
    record(top_level ? file_ : pending_, 0x05, m);
  }
  // Closes the pending chunk; returns its offset in the file.
  std::size_t chunk(const std::string& compression = "", bool corrupt_crc = false) {
    Bytes stored = pending_;
    if (compression == "zstd") {
      stored.resize(ZSTD_compressBound(pending_.size()));
      stored.resize(ZSTD_compress(stored.data(), stored.size(), pending_.data(), pending_.size(), 3));
    } else if (compression == "lz4") {
      stored.resize(LZ4F_compressFrameBound(pending_.size(), nullptr));
      stored.resize(LZ4F_compressFrame(stored.data(), stored.size(), pending_.data(), pending_.size(), nullptr));
    } else if (compression == "garbage-zstd") {
      stored.assign(40, 0x5a);
    }
    Bytes c;
    putLittle(c, 0, 8);
    putLittle(c, 0, 8);
    putLittle(c, pending_.size(), 8);
    putLittle(c, mcap::crc32(pending_.data(), pending_.size()) ^ (corrupt_crc ? 1u : 0u), 4);
    putString(c, compression == "garbage-zstd" ? "zstd" : compression);
    putLittle(c, stored.size(), 8);
    c.insert(c.end(), stored.begin(), stored.end());
    const std::size_t offset = file_.size();
    record(file_, 0x06, c);
    pending_.clear();
    return offset;
  }
  // An unknown record, which readers must skip.
  void unknownRecord() { record(file_, 0x80, Bytes(13, 0xee)); }
  std::string write(const std::string& path) {
    if (!pending_.empty()) chunk();
    Bytes end;
    putLittle(end, 0, 4);
    record(file_, 0x0F, end);
    Bytes footer(20, 0);
    record(file_, 0x02, footer);
    file_.insert(file_.end(), std::begin(mcap::kMagic), std::end(mcap::kMagic));
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file_.data()),
                                                 static_cast<std::streamsize>(file_.size()));
    return path;
  }

 private:
  static void putString(Bytes& out, const std::string& s) {
    putLittle(out, s.size(), 4);
    out.insert(out.end(), s.begin(), s.end());
  }
  static void record(Bytes& out, std::uint8_t opcode, const Bytes& body) {
    out.push_back(opcode);
    putLittle(out, body.size(), 8);
    out.insert(out.end(), body.begin(), body.end());
  }
  Bytes file_, pending_;
  std::map<std::string, std::uint16_t> channels_;
};

constexpr int kW = 4, kH = 3;
const char* kImages = "/cam/depth/image_raw";
const char* kInfo = "/cam/depth/camera_info";
const char* kPose = "/cam/pose";

std::vector<std::uint16_t> wall(std::uint16_t counts) {
  return std::vector<std::uint16_t>(kW * kH, counts);
}

// Images at 0, 1 and 2 s, each a wall at (1 + stamp) m; the first chunk
// holds the last image, so file order is not time order.
TestBag threeImageBag(const std::string& compression = "") {
  TestBag bag;
  bag.channel(kImages, "sensor_msgs/msg/Image");
  bag.channel(kInfo, "sensor_msgs/msg/CameraInfo");
  bag.channel(kPose, "geometry_msgs/msg/PoseStamped");
  bag.unknownRecord();
  bag.message(kInfo, cameraInfoMessage(kW, kH, 2.0, 2.5, 1.5, 1.0));
  bag.message(kImages, imageMessage(2.0, kW, kH, wall(3000)));
  bag.chunk(compression);
  bag.message(kImages, imageMessage(0.0, kW, kH, wall(1000)));
  bag.message(kImages, imageMessage(1.0, kW, kH, wall(2000)));
  bag.chunk(compression);
  return bag;
}

std::string bagPath(const std::string& name) {
  return (scratchFolder("mcap_" + name) / (name + ".mcap")).string();
}

TEST(CdrReader, DecodesAlignedFieldsInBothByteOrders) {
  for (bool little : {true, false}) {
    CdrWriter w(little);
    w.u8(7).u32(0x01020304u).f64(-1.5).str("ab").u16(0xBEEF).i32(-5);
    const Bytes& b = w.bytes();
    // Offsets after the 4-byte header: u8 at 0, u32 at 4, f64 at 8, string
    // length at 16 (3, with its NUL), u16 at 24, i32 at 28.
    ASSERT_EQ(b.size(), 4u + 32u);
    mcap::CdrReader r(b.data(), b.size(), "buffer", "message");
    EXPECT_EQ(r.littleEndian(), little);
    EXPECT_EQ(r.uint8(), 7);
    EXPECT_EQ(r.uint32(), 0x01020304u);
    EXPECT_EQ(r.float64(), -1.5);
    EXPECT_EQ(r.string(), "ab");
    EXPECT_EQ(r.uint16(), 0xBEEF);
    EXPECT_EQ(r.int32(), -5);
    EXPECT_EQ(r.remaining(), 0u);
  }
  // A hand-written little-endian buffer: u16 1, then a u32 two bytes later.
  const Bytes hand = {0x00, 0x01, 0x00, 0x00, 0x01, 0x00, 0xff, 0xff, 0x78, 0x56, 0x34, 0x12};
  mcap::CdrReader r(hand.data(), hand.size(), "hand", "");
  EXPECT_EQ(r.uint16(), 1);
  EXPECT_EQ(r.uint32(), 0x12345678u);
  // A u8, then a float64 8-aligned counting from after the header (1.0).
  const Bytes padded = {0x00, 0x01, 0x00, 0x00, 0x09, 0xaa, 0xaa, 0xaa, 0xaa, 0xaa, 0xaa, 0xaa,
                        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f};
  mcap::CdrReader p(padded.data(), padded.size(), "padded", "");
  EXPECT_EQ(p.uint8(), 9);
  EXPECT_EQ(p.float64(), 1.0);
  // Big endian: a string "hi" (length 3) then a u32.
  const Bytes big = {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x03, 'h', 'i', 0x00, 0xaa, 0x00, 0x00, 0x01, 0x02};
  mcap::CdrReader b(big.data(), big.size(), "big", "");
  EXPECT_EQ(b.string(), "hi");
  EXPECT_EQ(b.uint32(), 0x0102u);
}

TEST(CdrReader, RefusesTruncatedAndForeignBuffers) {
  const Bytes truncated = CdrWriter().u32(10).bytes();  // a 10-byte string with no characters
  const InputError e = expectInputError([&] {
    mcap::CdrReader r(truncated.data(), truncated.size(), "bag.mcap", "topic /x");
    r.string();
  });
  EXPECT_EQ(e.source(), "bag.mcap");
  EXPECT_EQ(e.location(), "topic /x");
  const Bytes xcdr2 = {0x00, 0x07, 0x00, 0x00};
  expectInputError([&] { mcap::CdrReader(xcdr2.data(), xcdr2.size(), "bag.mcap", ""); });
  const Bytes huge = CdrWriter().u32(0xFFFFFFFFu).bytes();
  expectInputError([&] {
    mcap::CdrReader r(huge.data(), huge.size(), "bag.mcap", "");
    r.sequenceLength(8);
  });
}

TEST(McapRecords, Crc32KnownAnswer) {
  const std::string text = "123456789";
  EXPECT_EQ(mcap::crc32(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), 0xCBF43926u);
}

TEST(McapReader, ReadsImagesInStampOrderWithTheCameraInfo) {
  const std::string path = threeImageBag().write(bagPath("order"));
  EXPECT_TRUE(isMcapFile(path));
  McapReaderOptions options;
  options.pose_topic = "";
  McapReader reader(path, options);
  EXPECT_EQ(reader.depthTopic(), kImages);
  EXPECT_EQ(reader.cameraInfoTopic(), kInfo);
  EXPECT_EQ(reader.depthEncoding(), "16UC1");
  EXPECT_EQ(reader.poseSource(), BagPoseSource::None);  // a pose topic without messages is no pose source
  EXPECT_EQ(reader.camera().intrinsics.fx, 2.0);
  EXPECT_EQ(reader.camera().intrinsics.fy, 2.5);
  EXPECT_EQ(reader.camera().intrinsics.width, kW);
  EXPECT_EQ(reader.camera().depth_scale, 1000.0);
  for (int i = 0; i < 3; ++i) {
    const std::optional<RangeScan> scan = reader.next();
    ASSERT_TRUE(scan);
    EXPECT_EQ(scan->index, static_cast<std::size_t>(i));
    EXPECT_EQ(scan->timestamp, static_cast<double>(i));
    ASSERT_EQ(scan->range.size(), static_cast<std::size_t>(kW * kH));
    EXPECT_NEAR(scan->range[5], 1.0 + i, 1e-6);
    // Identity optical pose: the point at the principal point lies on +z.
    ASSERT_FALSE(scan->points.empty());
  }
  EXPECT_FALSE(reader.next());
  EXPECT_EQ(reader.scansRead(), 3u);
}

TEST(McapReader, CompressedChunksReadAsUncompressedOnes) {
  const std::vector<RangeScan> plain = readScans(threeImageBag().write(bagPath("plain")));
  for (const char* compression : {"zstd", "lz4"}) {
    const std::vector<RangeScan> packed = readScans(threeImageBag(compression).write(bagPath(compression)));
    ASSERT_EQ(packed.size(), plain.size()) << compression;
    for (std::size_t i = 0; i < plain.size(); ++i) {
      EXPECT_EQ(packed[i].range, plain[i].range) << compression;
      EXPECT_EQ(packed[i].timestamp, plain[i].timestamp) << compression;
    }
  }
}

TEST(McapReader, InterpolatesPoseTopicBetweenMessages) {
  TestBag bag = threeImageBag();
  const Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  bag.message(kPose, poseMessage(0.0, Eigen::Vector3d(0, 0, 0), q0));
  bag.message(kPose, poseMessage(2.0, Eigen::Vector3d(2, 4, 0), q2), true);
  const std::string path = bag.write(bagPath("interpolate"));
  McapReaderOptions options;
  options.pose_topic = kPose;
  options.max_time_difference = 1.0;
  McapReader reader(path, options);
  EXPECT_EQ(reader.poseMatching(), "topic");
  const std::vector<double> angles = {0.0, M_PI / 4, M_PI / 2};
  for (int i = 0; i < 3; ++i) {
    const RangeScan scan = *reader.next();
    Eigen::Isometry3d optical = Eigen::Isometry3d::Identity();
    optical.linear() = Eigen::AngleAxisd(angles[static_cast<std::size_t>(i)], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    optical.translation() = Eigen::Vector3d(i, 2.0 * i, 0);
    const Eigen::Isometry3d expected = opticalToSensorPose(optical);
    EXPECT_LT((scan.sensor_pose.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12) << "image " << i;
  }
}

TEST(McapReader, ComposesTfChainsWithStaticEdges) {
  TestBag bag = threeImageBag();
  bag.channel("/tf", "tf2_msgs/msg/TFMessage");
  bag.channel("/tf_static", "tf2_msgs/msg/TFMessage");
  const Eigen::Quaterniond none = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  bag.message("/tf_static", tfMessage({{0.0, "base", "cam", Eigen::Vector3d(0, 0, 1), tilt}}));
  bag.message("/tf", tfMessage({{0.0, "/world", "base", Eigen::Vector3d(0, 0, 0), none},
                                {0.0, "world", "marker", Eigen::Vector3d(5, 0, 0), none}}));
  bag.message("/tf", tfMessage({{2.0, "world", "base", Eigen::Vector3d(2, 0, 0), none},
                                {2.0, "world", "marker", Eigen::Vector3d(5, 0, 0), none}}));
  const std::string path = bag.write(bagPath("tf"));

  McapReaderOptions options;
  options.parent_frame = "world";  // child: the images' frame_id, "cam"
  options.max_time_difference = 1.0;
  McapReader reader(path, options);
  EXPECT_EQ(reader.poseMatching(), "tf");
  Eigen::Isometry3d base_to_cam = Eigen::Isometry3d::Identity();
  base_to_cam.linear() = tilt.toRotationMatrix();
  base_to_cam.translation() = Eigen::Vector3d(0, 0, 1);
  for (int i = 0; i < 3; ++i) {
    const RangeScan scan = *reader.next();
    const Eigen::Isometry3d expected = opticalToSensorPose(Eigen::Translation3d(i, 0, 0) * base_to_cam);
    EXPECT_LT((scan.sensor_pose.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12) << "image " << i;
  }
  EXPECT_EQ(reader.childFrame(), "cam");

  // Across the tree: the camera seen from a sibling of its ancestor.
  options.parent_frame = "marker";
  options.child_frame = "cam";
  McapReader sibling(path, options);
  const RangeScan scan = *sibling.next();
  const Eigen::Isometry3d expected = opticalToSensorPose(Eigen::Translation3d(-5, 0, 0) * base_to_cam);
  EXPECT_LT((scan.sensor_pose.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12);

  options.parent_frame = "nowhere";
  const InputError e = expectInputError([&] { McapReader(path, options); });
  EXPECT_NE(e.location().find("nowhere"), std::string::npos) << e.what();
  // A dynamic edge without a message near an image names the frames and the image.
  options.parent_frame = "world";
  options.max_time_difference = 0.1;
  const InputError gap = expectInputError([&] { McapReader(path, options); });
  EXPECT_NE(gap.location().find("tf frames world -> cam"), std::string::npos) << gap.what();
  EXPECT_NE(gap.detail().find("'world' -> 'base'"), std::string::npos) << gap.what();
}

// A 32FC1 image in big-endian bytes with padded rows, in a big-endian CDR
// message: metres come back whatever the byte orders and the row step.
TEST(McapReader, ReadsBigEndianFloatImagesWithPaddedRows) {
  CdrWriter w(false);
  const std::uint32_t step = kW * 4 + 3;
  w.header(5.0, "cam").u32(kH).u32(kW).str("32FC1").u8(1).u32(step).u32(step * kH);
  Bytes data;
  for (int r = 0; r < kH; ++r) {
    for (int c = 0; c < kW; ++c) {
      const float metres = r == 1 && c == 2 ? std::nanf("") : 0.5f + 0.25f * static_cast<float>(r * kW + c);
      std::uint32_t bits;
      std::memcpy(&bits, &metres, 4);
      for (int b = 3; b >= 0; --b) data.push_back(static_cast<std::uint8_t>(bits >> (8 * b)));
    }
    data.insert(data.end(), 3, 0xcd);
  }
  w.raw(data);
  TestBag bag;
  bag.channel(kImages, "sensor_msgs/msg/Image");
  bag.channel(kInfo, "sensor_msgs/msg/CameraInfo");
  bag.message(kInfo, cameraInfoMessage(kW, kH, 2.0, 2.0, 1.5, 1.0));
  bag.message(kImages, w.bytes());
  McapReader reader(bag.write(bagPath("float")));
  EXPECT_EQ(reader.depthEncoding(), "32FC1");
  const RangeScan scan = *reader.next();
  EXPECT_EQ(scan.timestamp, 5.0);
  for (int i = 0; i < kW * kH; ++i) {
    const double expected = i == kW + 2 ? 0.0 : 0.5 + 0.25 * i;
    EXPECT_NEAR(scan.range[static_cast<std::size_t>(i)], expected, 1e-4) << "pixel " << i;
  }
}

TEST(McapReader, MissingCameraInfoIsNamedUnlessIntrinsicsAreGiven) {
  TestBag bag;
  bag.channel(kImages, "sensor_msgs/msg/Image");
  bag.message(kImages, imageMessage(0.0, kW, kH, wall(1000)));
  const std::string path = bag.write(bagPath("noinfo"));
  const InputError e = expectInputError([&] { McapReader reader(path); });
  EXPECT_EQ(e.source(), path);
  EXPECT_EQ(e.location(), "topic /cam/depth/camera_info") << e.what();
  McapReaderOptions options;
  options.intrinsics = CameraIntrinsics{0, 0, 2.0, 2.0, 1.5, 1.0};
  McapReader reader(path, options);
  EXPECT_TRUE(reader.camera().intrinsics_from_options);
  EXPECT_TRUE(reader.next());
}

TEST(McapReader, UnknownEncodingNamesTheTopic) {
  TestBag bag;
  bag.channel(kImages, "sensor_msgs/msg/Image");
  bag.channel(kInfo, "sensor_msgs/msg/CameraInfo");
  bag.message(kInfo, cameraInfoMessage(kW, kH, 2.0, 2.0, 1.5, 1.0));
  bag.message(kImages, imageMessage(0.0, kW, kH, wall(1000), "rgb8"));
  const InputError e = expectInputError([&] { McapReader reader(bag.write(bagPath("rgb8"))); });
  EXPECT_EQ(e.location(), std::string("topic ") + kImages) << e.what();
  EXPECT_NE(e.detail().find("'rgb8'"), std::string::npos) << e.what();
}

TEST(McapReader, CorruptChunksNameTheChunk) {
  for (const bool bad_crc : {true, false}) {
    TestBag bag;
    bag.channel(kImages, "sensor_msgs/msg/Image");
    bag.channel(kInfo, "sensor_msgs/msg/CameraInfo");
    bag.message(kInfo, cameraInfoMessage(kW, kH, 2.0, 2.0, 1.5, 1.0));
    bag.message(kImages, imageMessage(0.0, kW, kH, wall(1000)));
    const std::size_t offset = bag.chunk(bad_crc ? "" : "garbage-zstd", bad_crc);
    const InputError e = expectInputError([&] { McapReader reader(bag.write(bagPath("corrupt"))); });
    EXPECT_EQ(e.location(), "chunk at byte " + std::to_string(offset)) << e.what();
    EXPECT_NE(e.detail().find(bad_crc ? "CRC" : "zstd: "), std::string::npos) << e.what();
  }
}

TEST(McapReader, TruncatedAndForeignFilesAreRefused) {
  const std::string path = threeImageBag().write(bagPath("truncated"));
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 150);
  const InputError e = expectInputError([&] { readScans(path); });
  EXPECT_NE(e.location().find("byte"), std::string::npos) << e.what();
  const std::string other = (scratchFolder("mcap_foreign") / "x.mcap").string();
  std::ofstream(other) << "not a bag";
  EXPECT_FALSE(isMcapFile(other));
  expectInputError([&] { McapReader reader(other); });
}

TEST(McapReader, PoseGapNamesThePoseTopicAndTheImage) {
  TestBag bag = threeImageBag();
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  bag.message(kPose, poseMessage(0.0, Eigen::Vector3d::Zero(), q));
  bag.message(kPose, poseMessage(2.0, Eigen::Vector3d::Zero(), q));
  const std::string path = bag.write(bagPath("gap"));
  McapReaderOptions options;
  options.pose_topic = kPose;
  const InputError e = expectInputError([&] { McapReader reader(path, options); });
  EXPECT_EQ(e.location(), std::string("topic ") + kPose) << e.what();
  EXPECT_NE(e.detail().find("image 1"), std::string::npos) << e.what();
  EXPECT_NE(e.detail().find("1.000000000"), std::string::npos) << e.what();
  // The only PoseStamped topic is used without being named.
  options.pose_topic.clear();
  options.max_time_difference = 1.0;
  EXPECT_EQ(McapReader(path, options).poseMatching(), "topic");
  options.pose_topic = "/no/such/topic";
  const InputError missing = expectInputError([&] { McapReader reader(path, options); });
  EXPECT_EQ(missing.location(), "topic /no/such/topic");
}

TEST(McapReader, GroundTruthOfABagIsMatchedToItsImageStamps) {
  TestBag bag = threeImageBag();
  bag.message(kPose, poseMessage(0.0, Eigen::Vector3d(0, 0, 0), Eigen::Quaterniond::Identity()));
  bag.message(kPose, poseMessage(2.0, Eigen::Vector3d(2, 4, 0),
                                 Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))),
              true);
  const std::string path = bag.write(bagPath("ground_truth"));
  ReconstructionParameters params;
  params.mcap.pose_topic = kPose;
  params.mcap.max_time_difference = 1.0;
  // The truth: the images' optical poses shifted by 1 cm, two per image
  // stamp's neighbourhood so that it is matched by stamp, not by order.
  const std::string truth = (std::filesystem::path(path).parent_path() / "truth.txt").string();
  {
    std::ofstream out(truth);
    out.precision(17);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 4 * i, Eigen::Vector3d::UnitZ()));
      out << i - 0.5 << " 9 9 9 0 0 0 1\n";
      out << i << " " << i + 0.01 << " " << 2.0 * i << " 0 " << q.x() << " " << q.y() << " " << q.z() << " " << q.w()
          << "\n";
    }
  }
  const GroundTruthPoses read = readGroundTruthPoses(path, truth, params);
  ASSERT_EQ(read.poses.size(), 3u);
  McapReaderOptions options = params.mcap;
  McapReader reader(path, options);
  for (int i = 0; i < 3; ++i) {
    const RangeScan scan = *reader.next();
    EXPECT_DOUBLE_EQ(read.poses[static_cast<std::size_t>(i)].timestamp, scan.timestamp);
    Eigen::Isometry3d expected = scan.sensor_pose;
    expected.translation().x() += 0.01;
    EXPECT_LT((read.poses[static_cast<std::size_t>(i)].pose.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-9)
        << "image " << i;
  }
}

TEST(ScanReader, OpensBagsByTheirMagic) {
  const std::string path = threeImageBag().write(bagPath("scan_reader"));
  ScanReaderOptions options;
  options.depth_camera.depth_scale = 500.0;
  ScanReader reader(path, options);
  EXPECT_TRUE(reader.isBag());
  EXPECT_FALSE(reader.isFolder());
  ASSERT_TRUE(reader.depthCamera());
  EXPECT_EQ(reader.depthCamera()->depth_scale, 500.0);
  EXPECT_EQ(reader.poseMatching(), "none");
  EXPECT_NEAR(reader.next()->range[0], 2.0, 1e-6);  // 1000 counts at 500 per metre
  options.pose_file = "poses.txt";
  expectInputError([&] { ScanReader refused(path, options); });
}

}  // namespace
}  // namespace icrkit::reconstruction
