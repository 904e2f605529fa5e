#pragma once
/// \file
/// The ROS 2 messages a depth recording needs, decoded from CDR by field
/// order (their .msg definitions; the schema text in the bag is not parsed:
/// messages are recognised by the schema name).

#include "input/mcap/cdr_reader.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace icrkit::reconstruction::mcap {

inline constexpr const char* kImageSchema = "sensor_msgs/msg/Image";
inline constexpr const char* kCameraInfoSchema = "sensor_msgs/msg/CameraInfo";
inline constexpr const char* kPoseStampedSchema = "geometry_msgs/msg/PoseStamped";
inline constexpr const char* kTfSchema = "tf2_msgs/msg/TFMessage";

/// builtin_interfaces/Time.
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  double seconds() const;
};

/// std_msgs/Header.
struct RosHeader {
  RosTime stamp;
  std::string frame_id;
};

/// sensor_msgs/Image; `data` points into the message (not owned).
struct RosImage {
  RosHeader header;
  std::uint32_t height = 0, width = 0;
  std::string encoding;
  bool is_bigendian = false;
  std::uint32_t step = 0;  ///< bytes per row
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;
};

/// sensor_msgs/CameraInfo up to the projection (binning and ROI unused).
struct RosCameraInfo {
  RosHeader header;
  std::uint32_t height = 0, width = 0;
  std::string distortion_model;
  std::vector<double> d;
  std::array<double, 9> k{};
};

/// geometry_msgs/Transform or Pose: translation/position, rotation/orientation (x, y, z, w).
struct RosTransform {
  std::array<double, 3> translation{};
  std::array<double, 4> rotation_xyzw{};
};

struct RosPoseStamped {
  RosHeader header;
  RosTransform pose;
};

/// geometry_msgs/TransformStamped.
struct RosTransformStamped {
  RosHeader header;  ///< frame_id: the parent
  std::string child_frame_id;
  RosTransform transform;
};

RosHeader readHeader(CdrReader& cdr);
/// The header, size and encoding only: what the first pass needs.
RosImage readImageHeader(CdrReader& cdr);
/// The whole image, `data` checked to hold `step` x `height` bytes.
RosImage readImage(CdrReader& cdr);
RosCameraInfo readCameraInfo(CdrReader& cdr);
RosPoseStamped readPoseStamped(CdrReader& cdr);
std::vector<RosTransformStamped> readTfMessage(CdrReader& cdr);

}  // namespace icrkit::reconstruction::mcap
