#pragma once
// The options of a TUM RGB-D folder input (camera, depth scale, pose
// matching), shared by `icrkit reconstruct` and `icrkit convert`, and those
// of a ROS 2 bag input (topics, tf frames), which reuses --intrinsics,
// --depth-scale and --max-time-difference.
// Header-only so that the commands share it without another source file.

#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/reconstruction/input/mcap_reader.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace icrkit::app {

struct DepthFolderFlags {
  std::string intrinsics;
  double depth_scale = 0.0;
  std::string camera;
  double max_time_difference = reconstruction::kTumMaxTimeDifference;

  bool anyGiven(const CLI::App& command) const {
    return !intrinsics.empty() || depth_scale != 0.0 || !camera.empty() || command.count("--max-time-difference") > 0;
  }
};

inline void addDepthFolderOptions(CLI::App& command, DepthFolderFlags& flags) {
  command.add_option("--intrinsics", flags.intrinsics,
                     "TUM folder or ROS 2 bag input: the depth camera fx,fy,cx,cy[,k1,k2,p1,p2,k3] (pixels; "
                     "plumb-bob distortion); replaces the camera file's or the bag's CameraInfo");
  command.add_option("--depth-scale", flags.depth_scale,
                     "TUM folder or ROS 2 bag input: depth counts per metre (1000 = millimetres). Default: the camera "
                     "file's, else TUM's 5000; for a bag's 16UC1 images 1000 (REP 118)");
  command.add_option("--camera", flags.camera,
                     "TUM folder input: camera file (JSON: fx, fy, cx, cy, distortion_k1_k2_p1_p2_k3, depth_scale, "
                     "max_range_m; docs/reconstruction_input.md). Default: FOLDER/camera.json when present");
  command
      .add_option("--max-time-difference", flags.max_time_difference,
                  "TUM folder input: poses are matched to depth frames by order when their counts are equal, "
                  "else by nearest time stamp within this many seconds. ROS 2 bag: the farthest a pose (or tf) "
                  "message may lie from an image's stamp")
      ->capture_default_str();
}

/// A ROS 2 bag's topics and frames.
struct BagFlags {
  std::string depth_topic;
  std::string camera_info_topic;
  std::string pose_topic;
  std::string frames;  ///< PARENT[,CHILD]

  bool anyGiven() const {
    return !depth_topic.empty() || !camera_info_topic.empty() || !pose_topic.empty() || !frames.empty();
  }
};

inline void addBagOptions(CLI::App& command, BagFlags& flags) {
  command.add_option("--depth-topic", flags.depth_topic,
                     "ROS 2 bag input: sensor_msgs/msg/Image topic of the depth images (16UC1, 32FC1). Default: the "
                     "bag's only depth image topic");
  command.add_option("--camera-info-topic", flags.camera_info_topic,
                     "ROS 2 bag input: sensor_msgs/msg/CameraInfo topic. Default: camera_info beside the depth topic, "
                     "else the bag's only one (--intrinsics replaces it)");
  command.add_option("--pose-topic", flags.pose_topic,
                     "ROS 2 bag input: geometry_msgs/msg/PoseStamped topic of the camera's optical frame in the object "
                     "frame, interpolated at each image's stamp. Default: the bag's only PoseStamped topic, else "
                     "identity poses");
  command.add_option("--frames", flags.frames,
                     "ROS 2 bag input: poses from /tf and /tf_static, PARENT,CHILD: the object frame and the camera's "
                     "optical frame (CHILD default: the images' header.frame_id)");
}

/// The bag reader's options from the bag flags and the shared camera flags.
inline reconstruction::McapReaderOptions mcapReaderOptions(const BagFlags& flags, const DepthFolderFlags& camera);

/// "fx,fy,cx,cy" or "fx,fy,cx,cy,k1,k2,p1,p2,k3".
inline CameraIntrinsics parseIntrinsics(const std::string& text) {
  const std::vector<std::string> items = split(text, ',');
  double v[9] = {};
  if (items.size() != 4 && items.size() != 9)
    throw InputError("--intrinsics", "", "expected fx,fy,cx,cy or fx,fy,cx,cy,k1,k2,p1,p2,k3, got '" + text + "'");
  for (std::size_t i = 0; i < items.size(); ++i)
    if (!parseNumber(items[i], v[i]) || !std::isfinite(v[i]))
      throw InputError("--intrinsics", "", "'" + items[i] + "' is not a number");
  if (!(v[0] > 0 && v[1] > 0)) throw InputError("--intrinsics", "", "expected positive focal lengths fx, fy (pixels)");
  CameraIntrinsics k;
  k.fx = v[0];
  k.fy = v[1];
  k.cx = v[2];
  k.cy = v[3];
  for (std::size_t i = 0; i < 5; ++i) k.distortion[i] = v[4 + i];
  return k;
}

/// The library options; InputErrors name the flag (the library names
/// DepthCameraOptions::depth_scale, which the commands map to --depth-scale).
inline reconstruction::DepthCameraOptions depthCameraOptions(const DepthFolderFlags& flags) {
  reconstruction::DepthCameraOptions options;
  if (!flags.intrinsics.empty()) options.intrinsics = parseIntrinsics(flags.intrinsics);
  // 0: unset (the camera file's, else TUM's); the library checks the value
  // (DepthCameraOptions::depth_scale, mapped to --depth-scale by the commands).
  if (flags.depth_scale != 0.0) options.depth_scale = flags.depth_scale;
  options.camera_file = flags.camera;
  if (!(flags.max_time_difference >= 0) || !std::isfinite(flags.max_time_difference))
    throw InputError("--max-time-difference", "", "expected seconds >= 0");
  return options;
}

/// The options only a folder input takes, refused for a rawlog.
inline void refuseDepthFolderOptions(const CLI::App& command, const DepthFolderFlags& flags) {
  if (!flags.anyGiven(command)) return;
  const char* flag = !flags.intrinsics.empty()  ? "--intrinsics"
                     : flags.depth_scale != 0.0 ? "--depth-scale"
                     : !flags.camera.empty()    ? "--camera"
                                                : "--max-time-difference";
  throw InputError(flag, "",
                   "applies to a TUM RGB-D folder input; a rawlog carries its own camera (cameraParams, "
                   "rangeUnits) and matches poses by order");
}

inline reconstruction::McapReaderOptions mcapReaderOptions(const BagFlags& flags, const DepthFolderFlags& camera) {
  if (!camera.camera.empty())
    throw InputError("--camera", "", "applies to a TUM folder; a ROS 2 bag's camera is its CameraInfo (or --intrinsics)");
  reconstruction::McapReaderOptions options;
  options.depth_topic = flags.depth_topic;
  options.camera_info_topic = flags.camera_info_topic;
  options.pose_topic = flags.pose_topic;
  if (!flags.frames.empty()) {
    const std::vector<std::string> frames = split(flags.frames, ',');
    if (frames.empty() || frames.size() > 2 || frames[0].empty() || (frames.size() == 2 && frames[1].empty()))
      throw InputError("--frames", "", "expected PARENT or PARENT,CHILD (tf frame ids), got '" + flags.frames + "'");
    options.parent_frame = frames[0];
    if (frames.size() == 2) options.child_frame = frames[1];
  }
  if (!flags.pose_topic.empty() && !flags.frames.empty())
    throw InputError("--pose-topic", "", "give --pose-topic or --frames, not both");
  const reconstruction::DepthCameraOptions lens = depthCameraOptions(camera);
  options.intrinsics = lens.intrinsics;
  options.depth_scale = lens.depth_scale;
  options.max_time_difference = camera.max_time_difference;
  return options;
}

/// The options only a bag input takes, refused for a rawlog or a folder.
inline void refuseBagOptions(const BagFlags& flags, const char* input_kind) {
  if (!flags.anyGiven()) return;
  const char* flag = !flags.depth_topic.empty()         ? "--depth-topic"
                     : !flags.camera_info_topic.empty() ? "--camera-info-topic"
                     : !flags.pose_topic.empty()        ? "--pose-topic"
                                                        : "--frames";
  throw InputError(flag, "", std::string("applies to a ROS 2 bag (MCAP) input, not to a ") + input_kind);
}

/// The library's record of the camera (reconstruction::depthCameraRecordJson)
/// with the command line's names for values the options set.
inline nlohmann::json depthCameraJson(const reconstruction::DepthCamera& camera) {
  nlohmann::json record = nlohmann::json::parse(reconstruction::depthCameraRecordJson(camera));
  if (camera.intrinsics_from_options) record["intrinsics_source"] = "--intrinsics";
  if (camera.depth_scale_source == "options") record["depth_scale_source"] = "--depth-scale";
  return record;
}

/// A note when the depth scale is TUM's default: a folder in millimetres
/// read at 5000 counts per metre comes out five times too small.
inline std::string depthScaleNote(const reconstruction::DepthCamera& camera) {
  if (camera.depth_scale_source != "default") return {};
  return "icrkit: depth scale " + std::to_string(static_cast<int>(camera.depth_scale)) +
         " counts per metre (TUM's default); give --depth-scale (1000 for millimetres) if the images are not "
         "in TUM's units";
}

}  // namespace icrkit::app
