#pragma once
/// \file
/// Depth-image folders in the TUM RGB-D layout, the form most real depth
/// recordings are published in (docs/reconstruction_input.md, "TUM RGB-D
/// folders"):
///
///     FOLDER/depth.txt      '#' comments, then `timestamp filename` lines
///     FOLDER/depth/*.png    16-bit depth counts, 0 = no return
///     FOLDER/camera.json    optional: intrinsics and depth scale
///
/// plus an optional TUM trajectory of the camera's OPTICAL frame (x right,
/// y down, z forward) in the object frame. Each frame becomes the same
/// RangeScan a rawlog's CObservation3DRangeScan does: the image goes into an
/// MRPT observation and through the rawlog reader's conversion, so the
/// points are MRPT's unprojection of the pixels exactly as for a rawlog, and
/// the sensor pose is in MRPT's sensor axes (mrptSensorAxesInOptical()).

#include <icrkit/core/camera_intrinsics.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// TUM RGB-D's depth scale (counts per metre), the default when neither an
/// option nor a camera file gives one.
inline constexpr double kTumDepthScale = 5000.0;
/// TUM's associate.py default: the largest time difference (seconds) at
/// which a pose is matched to a depth frame by time stamp.
inline constexpr double kTumMaxTimeDifference = 0.02;

/// One line of depth.txt.
struct DepthFrame {
  double timestamp = 0.0;  ///< seconds, as listed
  std::string file;        ///< as listed
  std::string path;        ///< resolved against the folder (unless absolute)
  std::size_t line = 0;    ///< 1-based, in depth.txt
};

/// How the camera of a folder is given. Options override the camera file.
struct DepthCameraOptions {
  /// fx, fy, cx, cy and the plumb-bob distortion (width and height are
  /// ignored: they come from the images). Replaces the camera file's whole
  /// lens model. Unset: the camera file's.
  std::optional<CameraIntrinsics> intrinsics;
  /// Depth counts per metre (1000: millimetres; finite and > 0). Unset: the
  /// camera file's, else kTumDepthScale.
  std::optional<double> depth_scale;
  /// The camera file (JSON, below). Empty: FOLDER/camera.json when present.
  std::string camera_file;
};

/// The camera a folder is read with, and where each part came from.
struct DepthCamera {
  CameraIntrinsics intrinsics;  ///< width and height of the images
  double depth_scale = 0.0;     ///< counts per metre
  double max_range = 0.0;       ///< metres; 0: not given (rays are not cut in the fusion)
  std::string camera_file;      ///< the file read, or empty
  bool intrinsics_from_options = false;
  /// "options", "camera file" or "default" (kTumDepthScale).
  std::string depth_scale_source;
};

/// `camera` as the JSON object reconstruction.json records (keys sorted):
/// width, height, fx, fy, cx, cy, distortion_k1_k2_p1_p2_k3,
/// intrinsics_source ("options" or the camera file), depth_scale,
/// depth_scale_source ("options", the camera file or "default (TUM)"),
/// max_range_m.
std::string depthCameraRecordJson(const DepthCamera& camera);

/// How poses were assigned to the frames.
enum class PoseMatching {
  None,         ///< no pose file: every optical frame is the object frame
  ByOrder,      ///< as many poses as frames: pose i is frame i's
  ByTimestamp,  ///< otherwise: the pose nearest in time, within max_time_difference
};
const char* poseMatchingName(PoseMatching matching);  ///< "none", "order", "timestamp"

struct TumFolderOptions {
  /// TUM trajectory (`timestamp tx ty tz qx qy qz qw`) of the camera's
  /// OPTICAL frame (x right, y down, z forward) in the object frame, i.e.
  /// camera-to-object, as TUM's groundtruth.txt; matched to the frames as
  /// matchOpticalPoses() says. Empty: identity poses.
  std::string pose_file;
  DepthCameraOptions camera;
  double max_time_difference = kTumMaxTimeDifference;
  /// Compute the scans' `points` and `pixels`.
  bool unproject = true;
};

/// Reads the scans of a folder one at a time:
///
///     TumFolderReader reader("rec/", options);
///     while (auto scan = reader.next()) { ... }
///
/// The list, the camera, the poses and the existence of every listed image
/// are checked on construction; each image is decoded by next(). Throws
/// InputError naming the file (depth.txt and its line, the image and its
/// scan, the camera file and its key, the pose file and its scan).
class TumFolderReader {
 public:
  explicit TumFolderReader(const std::string& folder, TumFolderOptions options = {});
  ~TumFolderReader();
  TumFolderReader(const TumFolderReader&) = delete;
  TumFolderReader& operator=(const TumFolderReader&) = delete;

  /// The next scan, or nothing after the last listed frame.
  std::optional<RangeScan> next();
  std::size_t scansRead() const;
  const std::string& path() const;
  const std::vector<DepthFrame>& frames() const;
  const DepthCamera& camera() const;
  PoseMatching poseMatching() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Parses a TUM image list (depth.txt): '#' comments and blank lines
/// skipped, then `timestamp filename` per line. Throws InputError naming the
/// file and the line for anything else, and for a list without frames.
std::vector<DepthFrame> readDepthList(const std::string& list_file);

/// Reads the camera file: a JSON object with `fx`, `fy`, `cx`, `cy`
/// (pixels), optional `distortion_k1_k2_p1_p2_k3` (5 numbers), `width` and
/// `height` (checked against the images), `depth_scale` (counts per metre)
/// and `max_range_m`; the lens keys may instead sit in a `camera` object
/// (the file `icrkit calibrate -o` writes). Missing keys stay 0 in the
/// result. Throws InputError naming the file and the key.
DepthCamera readDepthCameraFile(const std::string& path);

/// Camera poses for frames: a TUM trajectory of optical-frame poses, as
/// many as `frame_timestamps` (matched by order) or any other number
/// (each frame takes the pose nearest in time, which must lie within
/// `max_time_difference`; the poses' time stamps must not decrease).
/// Returned in MRPT's sensor axes, one per frame, with `normalised` flags
/// (readTumTrajectory's). Throws InputError naming the pose file and the
/// scan that has no pose.
struct MatchedPoses {
  std::vector<Eigen::Isometry3d> sensor_poses;  ///< object frame, MRPT sensor axes
  std::vector<std::uint8_t> normalised;
  PoseMatching matching = PoseMatching::ByOrder;
};
MatchedPoses matchOpticalPoses(const std::string& pose_file, const std::vector<double>& frame_timestamps,
                               double max_time_difference = kTumMaxTimeDifference);

}  // namespace icrkit::reconstruction
