#pragma once
/// \file
/// ROS 2 bags in MCAP, read without ROS (docs/reconstruction_input.md,
/// "ROS 2 bags (MCAP)"): sensor_msgs/Image depth (16UC1, 32FC1) with its
/// sensor_msgs/CameraInfo, poses from a geometry_msgs/PoseStamped topic or
/// from /tf and /tf_static. Each image becomes the RangeScan a TUM folder
/// holding the same depth image and pose gives (depth_image_scan.hpp).

#include <icrkit/core/camera_intrinsics.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

struct McapReaderOptions {
  /// sensor_msgs/msg/Image topic of depth images (16UC1 or 32FC1). Empty:
  /// the bag's only such topic.
  std::string depth_topic;
  /// sensor_msgs/msg/CameraInfo topic. Empty: the depth topic's sibling
  /// `camera_info` (…/image_raw -> …/camera_info), else the only one.
  std::string camera_info_topic;
  /// geometry_msgs/msg/PoseStamped topic: the camera's optical frame in the
  /// object frame. Exclusive with `parent_frame`.
  std::string pose_topic;
  /// Poses from /tf and /tf_static: the transform from `parent_frame` (the
  /// object frame) to `child_frame` (empty: the images' header.frame_id).
  std::string parent_frame;
  std::string child_frame;
  /// A pose (or each transform of a tf chain) is interpolated between the
  /// messages around the image's stamp; none within this (seconds): error.
  double max_time_difference = 0.02;
  /// 16UC1 counts per metre. Unset: 1000 (REP 118: millimetres).
  std::optional<double> depth_scale;
  /// Replaces the CameraInfo's intrinsics and distortion (the bag then
  /// needs no CameraInfo).
  std::optional<CameraIntrinsics> intrinsics;
  bool unproject = true;
};

/// True when `path` is a file starting with MCAP's magic bytes.
bool isMcapFile(const std::string& path);

/// Where a bag's poses come from.
enum class BagPoseSource {
  None,   ///< identity: every optical frame is the object frame
  Topic,  ///< a PoseStamped topic (McapReaderOptions::pose_topic, or the bag's only one)
  Tf,     ///< the tf chain parent_frame -> child_frame
};
const char* bagPoseSourceName(BagPoseSource source);  ///< "none", "topic", "tf"

/// Reads the depth images of a bag one at a time, in the order of their
/// header stamps (equal stamps: file order):
///
///     McapReader reader("rec.mcap", options);
///     while (auto scan = reader.next()) { ... }
///
/// The constructor reads the bag once: topics, the camera, every pose and
/// where each image lies; the poses of all images are computed then, so
/// that a bag without a pose for some image fails before any scan. next()
/// decodes one image (its chunk is decompressed again, once per chunk when
/// images lie in file order). Throws InputError naming the bag and the
/// topic, the message or the record ("chunk at byte N").
class McapReader {
 public:
  explicit McapReader(const std::string& path, McapReaderOptions options = {});
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  std::optional<RangeScan> next();
  std::size_t scansRead() const;
  /// The number of depth images.
  std::size_t scanCount() const;
  /// Their header stamps (seconds), in the order next() returns them.
  std::vector<double> imageStamps() const;
  /// The largest time difference (seconds) a pose was matched over.
  double maxTimeDifference() const;
  const std::string& path() const;
  /// intrinsics (the CameraInfo's, or the options'), the images' size,
  /// depth_scale (16UC1 counts per metre) and where they came from;
  /// camera_file is the CameraInfo topic.
  const DepthCamera& camera() const;
  BagPoseSource poseSource() const;
  /// "topic", "tf" or "none" (bagPoseSourceName).
  std::string poseMatching() const;
  const std::string& depthTopic() const;
  const std::string& cameraInfoTopic() const;  ///< empty when the intrinsics came from the options only
  const std::string& poseTopic() const;        ///< empty unless poseSource() is Topic
  const std::string& parentFrame() const;      ///< set when poseSource() is Tf
  const std::string& childFrame() const;       ///< set when poseSource() is Tf
  const std::string& depthEncoding() const;    ///< 16UC1 or 32FC1

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace icrkit::reconstruction
