/// \file
/// McapReader: the first pass over a bag collects topics, the camera, the
/// poses and where each depth image lies; next() decodes one image at a time.

#include <icrkit/reconstruction/input/mcap_reader.hpp>

#include "input/mcap/cdr_reader.hpp"
#include "input/mcap/mcap_records.hpp"
#include "input/mcap/ros_messages.hpp"
#include "input/mcap/transform_lookup.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/reconstruction/input/depth_image_scan.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <system_error>
#include <vector>

namespace icrkit::reconstruction {
namespace {

using namespace mcap;

// REP 118: 16-bit depth images are in millimetres.
constexpr double kRosDepthScale = 1000.0;

std::string seconds(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9f", value);
  return text;
}

std::string topicLocation(const std::string& topic) {
  return "topic " + topic;
}

std::string messageLocation(const std::string& topic, const MessageLocation& location) {
  return "topic " + topic + ", message in the " + describe(location);
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text.empty() ? "none" : text;
}

enum class DepthEncoding { Counts16, Metres32, Unknown };

DepthEncoding encodingKind(const std::string& encoding) {
  // mono16 is what some drivers call their millimetre images.
  if (encoding == "16UC1" || encoding == "mono16") return DepthEncoding::Counts16;
  if (encoding == "32FC1") return DepthEncoding::Metres32;
  return DepthEncoding::Unknown;
}

struct TopicInfo {
  std::string schema_name;
  std::string message_encoding;
  std::size_t messages = 0;
};

struct ImageEntry {
  double stamp = 0.0;
  std::string frame_id;
  std::string encoding;
  std::uint32_t width = 0, height = 0;
  MessageLocation location;
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  bool pose_normalised = false;
};

std::string sibling(const std::string& topic, const std::string& name) {
  const std::size_t slash = topic.rfind('/');
  return slash == std::string::npos ? name : topic.substr(0, slash + 1) + name;
}

}  // namespace

const char* bagPoseSourceName(BagPoseSource source) {
  switch (source) {
    case BagPoseSource::Topic:
      return "topic";
    case BagPoseSource::Tf:
      return "tf";
    case BagPoseSource::None:
      return "none";
  }
  return "none";
}

bool isMcapFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;
  std::ifstream in(path, std::ios::binary);
  unsigned char magic[sizeof kMagic] = {};
  return in.read(reinterpret_cast<char*>(magic), sizeof magic) && std::memcmp(magic, kMagic, sizeof kMagic) == 0;
}

struct McapReader::Impl {
  McapReaderOptions options;
  RecordFile file;
  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, Channel> channels;
  std::map<std::string, TopicInfo> topics;
  std::map<std::string, std::vector<ImageEntry>> images_by_topic;
  std::map<std::string, RosCameraInfo> first_camera_info;
  std::map<std::string, PoseSeries> poses_by_topic;
  TransformTree tf;
  bool has_tf = false;

  std::vector<ImageEntry> images;
  std::string depth_topic, camera_info_topic, pose_topic, parent_frame, child_frame, encoding;
  DepthCamera camera;
  BagPoseSource pose_source = BagPoseSource::None;
  std::size_t scans = 0;
  std::vector<std::uint16_t> counts;
  std::vector<float> metres;

  Impl(const std::string& path, McapReaderOptions opts) : options(std::move(opts)), file(path) {}
  const std::string& path() const { return file.path(); }

  void collect(const MessageView& message) {
    const auto channel = channels.find(message.channel_id);
    if (channel == channels.end())
      throw InputError(path(), describe(message.location),
                       "a message on channel " + std::to_string(message.channel_id) +
                           ", which no Channel record declared before it");
    const std::string& topic = channel->second.topic;
    TopicInfo& info = topics[topic];
    ++info.messages;
    if (info.message_encoding != "cdr") return;
    const std::string where = messageLocation(topic, message.location);
    CdrReader cdr(message.data, message.size, path(), where);
    if (info.schema_name == kImageSchema) {
      const RosImage image = readImageHeader(cdr);
      ImageEntry entry;
      entry.stamp = image.header.stamp.seconds();
      entry.frame_id = image.header.frame_id;
      entry.encoding = image.encoding;
      entry.width = image.width;
      entry.height = image.height;
      entry.location = message.location;
      images_by_topic[topic].push_back(std::move(entry));
    } else if (info.schema_name == kCameraInfoSchema) {
      if (first_camera_info.count(topic) == 0) first_camera_info[topic] = readCameraInfo(cdr);
    } else if (info.schema_name == kPoseStampedSchema) {
      const RosPoseStamped pose = readPoseStamped(cdr);
      poses_by_topic[topic].add(pose.header.stamp.seconds(), pose.pose, path(), where);
    } else if (info.schema_name == kTfSchema) {
      const std::string name = tfFrameName(topic);
      if (name != "tf" && name != "tf_static") return;
      for (const RosTransformStamped& transform : readTfMessage(cdr)) tf.add(transform, name == "tf_static", path(), where);
      has_tf = true;
    }
  }

  void firstPass() {
    file.readAll([&](const Schema& schema) { schemas[schema.id] = schema; },
                 [&](const Channel& channel) {
                   const auto schema = schemas.find(channel.schema_id);
                   const std::string schema_name = schema == schemas.end() ? std::string() : schema->second.name;
                   const auto [it, inserted] = topics.try_emplace(channel.topic);
                   TopicInfo& info = it->second;
                   // Channels are repeated (per chunk, per publisher); a topic
                   // whose type changes would mix messages of two types.
                   if (!inserted && (info.schema_name != schema_name || info.message_encoding != channel.message_encoding))
                     throw InputError(path(), topicLocation(channel.topic),
                                      "declared again as " + schema_name + " in '" + channel.message_encoding +
                                          "', first as " + info.schema_name + " in '" + info.message_encoding + "'");
                   info.schema_name = schema_name;
                   info.message_encoding = channel.message_encoding;
                   channels[channel.id] = channel;
                 },
                 [&](const MessageView& message) { collect(message); });
    for (auto& [topic, series] : poses_by_topic) series.finish();
    tf.finish();
  }

  std::vector<std::string> topicsOf(const char* schema) const {
    std::vector<std::string> names;
    for (const auto& [topic, info] : topics)
      if (info.schema_name == schema) names.push_back(topic);
    return names;
  }

  // The topic must exist, carry `schema` in CDR and hold messages.
  void requireTopic(const std::string& topic, const char* schema, const char* option) const {
    const auto it = topics.find(topic);
    if (it == topics.end())
      throw InputError(path(), topicLocation(topic),
                       std::string("no such topic (") + option + "); the bag's " + schema +
                           " topics: " + joined(topicsOf(schema)));
    if (it->second.schema_name != schema)
      throw InputError(path(), topicLocation(topic),
                       "carries " + (it->second.schema_name.empty() ? std::string("no schema") : it->second.schema_name) +
                           ", expected " + schema);
    if (it->second.message_encoding != "cdr")
      throw InputError(path(), topicLocation(topic),
                       "its messages are encoded as '" + it->second.message_encoding +
                           "', expected 'cdr' (ROS 2)");
    const bool decoded = (std::strcmp(schema, kImageSchema) == 0 && images_by_topic.count(topic) > 0) ||
                         (std::strcmp(schema, kCameraInfoSchema) == 0 && first_camera_info.count(topic) > 0) ||
                         (std::strcmp(schema, kPoseStampedSchema) == 0 && poses_by_topic.count(topic) > 0 &&
                          !poses_by_topic.at(topic).empty());
    if (it->second.messages == 0 || !decoded) throw InputError(path(), topicLocation(topic), "holds no message");
  }

  void chooseDepthTopic() {
    if (!options.depth_topic.empty()) {
      depth_topic = options.depth_topic;
      requireTopic(depth_topic, kImageSchema, "McapReaderOptions::depth_topic");
    } else {
      const std::vector<std::string> image_topics = topicsOf(kImageSchema);
      std::vector<std::string> depth_topics;
      for (const std::string& topic : image_topics) {
        const auto it = images_by_topic.find(topic);
        if (it != images_by_topic.end() && !it->second.empty() &&
            encodingKind(it->second.front().encoding) != DepthEncoding::Unknown)
          depth_topics.push_back(topic);
      }
      if (depth_topics.size() > 1)
        throw InputError(path(), "",
                         "has several depth image topics (" + joined(depth_topics) +
                             "); choose one with McapReaderOptions::depth_topic");
      if (depth_topics.empty() && image_topics.size() != 1)
        throw InputError(path(), "",
                         "has no depth image topic (sensor_msgs/msg/Image in 16UC1 or 32FC1; image topics: " +
                             joined(image_topics) + ")");
      depth_topic = depth_topics.empty() ? image_topics.front() : depth_topics.front();
      requireTopic(depth_topic, kImageSchema, "McapReaderOptions::depth_topic");
    }
    images = images_by_topic[depth_topic];
    encoding = images.front().encoding;
    if (encodingKind(encoding) == DepthEncoding::Unknown)
      throw InputError(path(), topicLocation(depth_topic),
                       "unknown depth image encoding '" + encoding +
                           "' (expected 16UC1 in depth units or 32FC1 in metres; compressed images are not read)");
    // Scans in time order, whatever the order of the chunks.
    std::stable_sort(images.begin(), images.end(),
                     [](const ImageEntry& a, const ImageEntry& b) { return a.stamp < b.stamp; });
  }

  void resolveCamera() {
    const ImageEntry& first = images.front();
    if (first.width == 0 || first.height == 0 || first.width > 1u << 16 || first.height > 1u << 16)
      throw InputError(path(), messageLocation(depth_topic, first.location),
                       "expected an image size of 1x1 to 65536x65536 pixels, found " + std::to_string(first.width) +
                           "x" + std::to_string(first.height));
    if (!options.camera_info_topic.empty()) {
      camera_info_topic = options.camera_info_topic;
    } else {
      const std::vector<std::string> infos = topicsOf(kCameraInfoSchema);
      const std::string next_to_images = sibling(depth_topic, "camera_info");
      if (std::find(infos.begin(), infos.end(), next_to_images) != infos.end())
        camera_info_topic = next_to_images;
      else if (infos.size() == 1)
        camera_info_topic = infos.front();
      else if (!options.intrinsics)
        throw InputError(path(), topicLocation(next_to_images),
                         "no sensor_msgs/msg/CameraInfo for the depth images on " + depth_topic +
                             " (CameraInfo topics: " + joined(infos) +
                             "); choose one with McapReaderOptions::camera_info_topic or give "
                             "McapReaderOptions::intrinsics");
    }
    CameraIntrinsics& k = camera.intrinsics;
    if (!camera_info_topic.empty() && !(options.intrinsics && options.camera_info_topic.empty())) {
      requireTopic(camera_info_topic, kCameraInfoSchema, "McapReaderOptions::camera_info_topic");
      const RosCameraInfo& info = first_camera_info.at(camera_info_topic);
      const std::string where = topicLocation(camera_info_topic);
      if ((info.width != 0 || info.height != 0) && (info.width != first.width || info.height != first.height))
        throw InputError(path(), where,
                         "the camera is " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                             " but the images on " + depth_topic + " are " + std::to_string(first.width) + "x" +
                             std::to_string(first.height));
      k.fx = info.k[0];
      k.cx = info.k[2];
      k.fy = info.k[4];
      k.cy = info.k[5];
      const bool lens_model = info.distortion_model.empty() || info.distortion_model == "plumb_bob" ||
                              info.distortion_model == "rational_polynomial";
      for (std::size_t i = 0; i < info.d.size(); ++i) {
        if (!std::isfinite(info.d[i]))
          throw InputError(path(), where, "the distortion coefficients hold a non-finite number");
        if (i < 5 && lens_model) {
          k.distortion[i] = info.d[i];
        } else if (info.d[i] != 0.0) {
          throw InputError(path(), where,
                           "distortion model '" + info.distortion_model + "' with " + std::to_string(info.d.size()) +
                               " coefficients: only plumb-bob's k1 k2 p1 p2 k3 are supported (give "
                               "McapReaderOptions::intrinsics to replace them)");
        }
      }
      camera.camera_file = camera_info_topic;
    } else {
      camera_info_topic.clear();
    }
    if (options.intrinsics) {
      k = *options.intrinsics;
      camera.intrinsics_from_options = true;
    }
    k.width = static_cast<int>(first.width);
    k.height = static_cast<int>(first.height);
    if (!(k.fx > 0 && k.fy > 0 && std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) &&
          std::isfinite(k.cy)))
      throw InputError(path(), camera.intrinsics_from_options ? "McapReaderOptions::intrinsics" : topicLocation(camera_info_topic),
                       "expected positive focal lengths (K[0], K[4]) and a finite principal point (K[2], K[5])");
    if (options.depth_scale) {
      if (!(std::isfinite(*options.depth_scale) && *options.depth_scale > 0))
        throw InputError("McapReaderOptions::depth_scale", "", "expected the depth counts per metre (> 0)");
      camera.depth_scale = *options.depth_scale;
      camera.depth_scale_source = "options";
    } else {
      camera.depth_scale = kRosDepthScale;
      camera.depth_scale_source = "default (REP 118: millimetres)";
    }
  }

  void assignPoses() {
    if (!(options.max_time_difference >= 0) || !std::isfinite(options.max_time_difference))
      throw InputError("McapReaderOptions::max_time_difference", "", "expected seconds >= 0");
    if (!options.pose_topic.empty() && !options.parent_frame.empty())
      throw InputError("McapReaderOptions::pose_topic", "",
                       "give a pose topic or tf frames (McapReaderOptions::parent_frame), not both");
    if (options.parent_frame.empty() && !options.child_frame.empty())
      throw InputError("McapReaderOptions::parent_frame", "", "a child frame needs its parent (the object frame)");
    if (!options.parent_frame.empty()) {
      pose_source = BagPoseSource::Tf;
      parent_frame = tfFrameName(options.parent_frame);
      if (!has_tf) throw InputError(path(), "topic /tf", "holds no transform (tf2_msgs/msg/TFMessage on /tf or /tf_static)");
      if (!tf.hasFrame(parent_frame))
        throw InputError(path(), "tf frame " + parent_frame, "no transform in /tf or /tf_static names this frame");
    } else {
      pose_topic = options.pose_topic;
      if (pose_topic.empty()) {
        // The bag's only pose topic is the camera's; with none or several
        // there is no telling, and the images are taken as they are.
        const std::vector<std::string> pose_topics = topicsOf(kPoseStampedSchema);
        if (pose_topics.size() == 1 && poses_by_topic.count(pose_topics.front()) > 0) pose_topic = pose_topics.front();
      } else {
        requireTopic(pose_topic, kPoseStampedSchema, "McapReaderOptions::pose_topic");
      }
      pose_source = pose_topic.empty() ? BagPoseSource::None : BagPoseSource::Topic;
    }

    for (std::size_t i = 0; i < images.size(); ++i) {
      ImageEntry& image = images[i];
      const std::string image_name =
          "image " + std::to_string(i) + " of " + depth_topic + " (stamp " + seconds(image.stamp) + ")";
      PoseSample optical;
      if (pose_source == BagPoseSource::Topic) {
        double nearest = 0.0;
        const std::optional<PoseSample> sample =
            poses_by_topic.at(pose_topic).at(image.stamp, options.max_time_difference, nearest);
        if (!sample)
          throw InputError(path(), topicLocation(pose_topic),
                           "no pose within " + seconds(options.max_time_difference) + " s of " + image_name +
                               " (nearest: " + seconds(nearest) + ")");
        optical = *sample;
      } else if (pose_source == BagPoseSource::Tf) {
        const std::string child = options.child_frame.empty() ? tfFrameName(image.frame_id) : tfFrameName(options.child_frame);
        if (child.empty())
          throw InputError(path(), topicLocation(depth_topic),
                           image_name + " has no header.frame_id; give McapReaderOptions::child_frame");
        if (child_frame.empty()) child_frame = child;
        optical = tf.lookup(parent_frame, child, image.stamp, options.max_time_difference, path(),
                            "tf frames " + parent_frame + " -> " + child + ", " + image_name);
      }
      image.sensor_pose = opticalToSensorPose(optical.pose);
      image.pose_normalised = optical.normalised;
    }
  }

  RangeScan convert(std::size_t index) {
    const ImageEntry& entry = images[index];
    const MessageView message = file.messageAt(entry.location);
    const std::string where = messageLocation(depth_topic, entry.location);
    CdrReader cdr(message.data, message.size, path(), where);
    const RosImage image = readImage(cdr);
    const std::string scan_where = "scan " + std::to_string(index) + " (" + where + ")";
    if (image.encoding != encoding)
      throw InputError(path(), scan_where,
                       "the image is encoded as '" + image.encoding + "', the first one as '" + encoding + "'");
    if (static_cast<int>(image.width) != camera.intrinsics.width ||
        static_cast<int>(image.height) != camera.intrinsics.height)
      throw InputError(path(), scan_where,
                       "expected a " + std::to_string(camera.intrinsics.width) + "x" +
                           std::to_string(camera.intrinsics.height) + " image like the first, found " +
                           std::to_string(image.width) + "x" + std::to_string(image.height));
    const bool sixteen_bits = encodingKind(encoding) == DepthEncoding::Counts16;
    const std::size_t pixel_bytes = sixteen_bits ? 2 : 4;
    const std::size_t row_bytes = static_cast<std::size_t>(image.width) * pixel_bytes;
    if (image.step < row_bytes)
      throw InputError(path(), scan_where,
                       "the row step " + std::to_string(image.step) + " is shorter than a row of " +
                           std::to_string(row_bytes) + " bytes");
    // Rows copied out of the message: it guarantees no alignment, and its
    // byte order may not be ours.
    const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
    std::vector<std::uint8_t> packed(pixels * pixel_bytes);
    for (std::uint32_t r = 0; r < image.height; ++r)
      std::memcpy(packed.data() + r * row_bytes, image.data + static_cast<std::size_t>(r) * image.step, row_bytes);
    const std::uint16_t probe = 1;
    const bool host_big_endian = *reinterpret_cast<const std::uint8_t*>(&probe) == 0;
    if (image.is_bigendian != host_big_endian)
      for (std::size_t p = 0; p < packed.size(); p += pixel_bytes) std::reverse(packed.data() + p, packed.data() + p + pixel_bytes);

    DepthImageView view;
    view.width = static_cast<int>(image.width);
    view.height = static_cast<int>(image.height);
    if (sixteen_bits) {
      counts.resize(pixels);
      std::memcpy(counts.data(), packed.data(), packed.size());
      view.counts = counts.data();
      view.depth_scale = camera.depth_scale;
    } else {
      metres.resize(pixels);
      std::memcpy(metres.data(), packed.data(), packed.size());
      view.metres = metres.data();
    }
    DepthImageMeta meta;
    meta.intrinsics = camera.intrinsics;
    meta.sensor_pose = entry.sensor_pose;
    meta.pose_normalised = entry.pose_normalised;
    meta.timestamp = entry.stamp;
    meta.max_range = camera.max_range;
    meta.sensor_label = "ROS2_DEPTH";
    meta.unproject = options.unproject;
    return scanFromDepthImage(view, meta, index, path());
  }
};

McapReader::McapReader(const std::string& path, McapReaderOptions options)
    : impl_(std::make_unique<Impl>(path, std::move(options))) {
  impl_->firstPass();
  impl_->chooseDepthTopic();
  impl_->resolveCamera();
  impl_->assignPoses();
}

McapReader::~McapReader() = default;

std::optional<RangeScan> McapReader::next() {
  if (impl_->scans >= impl_->images.size()) return std::nullopt;
  RangeScan scan = impl_->convert(impl_->scans);
  ++impl_->scans;
  return scan;
}

std::size_t McapReader::scansRead() const {
  return impl_->scans;
}
std::size_t McapReader::scanCount() const {
  return impl_->images.size();
}
double McapReader::maxTimeDifference() const {
  return impl_->options.max_time_difference;
}
std::vector<double> McapReader::imageStamps() const {
  std::vector<double> stamps;
  for (const ImageEntry& image : impl_->images) stamps.push_back(image.stamp);
  return stamps;
}
const std::string& McapReader::path() const {
  return impl_->path();
}
const DepthCamera& McapReader::camera() const {
  return impl_->camera;
}
BagPoseSource McapReader::poseSource() const {
  return impl_->pose_source;
}
std::string McapReader::poseMatching() const {
  return bagPoseSourceName(impl_->pose_source);
}
const std::string& McapReader::depthTopic() const {
  return impl_->depth_topic;
}
const std::string& McapReader::cameraInfoTopic() const {
  return impl_->camera_info_topic;
}
const std::string& McapReader::poseTopic() const {
  return impl_->pose_topic;
}
const std::string& McapReader::parentFrame() const {
  return impl_->parent_frame;
}
const std::string& McapReader::childFrame() const {
  return impl_->child_frame;
}
const std::string& McapReader::depthEncoding() const {
  return impl_->encoding;
}

}  // namespace icrkit::reconstruction
