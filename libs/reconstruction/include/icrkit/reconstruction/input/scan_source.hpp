#pragma once
/// \file
/// One way to read a recording, whatever its form: an MRPT rawlog
/// (rawlog_reader.hpp), a TUM RGB-D folder of depth images
/// (tum_folder_reader.hpp) or a ROS 2 bag in MCAP (mcap_reader.hpp). A
/// folder is recognised by being a directory, a bag by MCAP's magic bytes.
/// All give the same RangeScan: range in metres, sensor pose in MRPT's
/// sensor axes, points unprojected by MRPT.

#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/input/mcap_reader.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

struct ScanReaderOptions {
  /// TUM trajectory replacing the recorded poses. Rawlog: MRPT sensor
  /// axes, pose i for scan i (RawlogReaderOptions). Folder: the camera's
  /// OPTICAL frame (x right, y down, z forward), camera-to-object, matched
  /// by order or time stamp (TumFolderOptions).
  std::string pose_file;
  /// Rawlog only: its externally stored images.
  std::string images_folder;
  /// Folder only: intrinsics, depth scale, camera file. A bag takes
  /// `intrinsics` and `depth_scale` from here when `mcap` leaves them unset
  /// (a camera file is refused for a bag).
  DepthCameraOptions depth_camera;
  /// Folder: pose-to-frame matching by time stamp. Bag: how far a pose
  /// message may lie from an image's stamp (replaces mcap's when not the default).
  double max_time_difference = kTumMaxTimeDifference;
  /// Bag only: topics, frames, depth scale (McapReaderOptions).
  McapReaderOptions mcap;
  /// Rawlog only: how far a recorded rotation matrix may be off orthonormal.
  double rotation_tolerance = kReadRotationTolerance;
  bool unproject = true;
};

/// True when `path` is read as a TUM RGB-D folder (it is a directory).
bool isDepthImageFolder(const std::string& path);

/// True when `path` is read as a ROS 2 bag (a file starting with MCAP's magic).
bool isBag(const std::string& path);

/// Reads the scans of a rawlog, a folder or a bag one at a time:
///
///     ScanReader reader(path, options);
///     while (auto scan = reader.next()) { ... }
///
/// Throws the InputErrors of the reader it opens.
class ScanReader {
 public:
  explicit ScanReader(const std::string& path, const ScanReaderOptions& options = {});
  ~ScanReader();
  ScanReader(const ScanReader&) = delete;
  ScanReader& operator=(const ScanReader&) = delete;

  std::optional<RangeScan> next();
  std::size_t scansRead() const;
  const std::string& path() const;
  bool isFolder() const;
  bool isBag() const;
  /// The bag's reader (its topics and frames), or null.
  const McapReader* bag() const;
  /// The folder's or the bag's camera; nothing for a rawlog (its scans carry theirs).
  std::optional<DepthCamera> depthCamera() const;
  /// How the poses were assigned: rawlog: "recorded" (sensorPose) or
  /// "order" (the pose file); folder: poseMatchingName(); bag:
  /// bagPoseSourceName() ("topic", "tf", "none").
  std::string poseMatching() const;

 private:
  std::unique_ptr<RawlogReader> rawlog_;
  std::unique_ptr<TumFolderReader> folder_;
  std::unique_ptr<McapReader> bag_;
  bool pose_file_ = false;
};

/// Every scan of a rawlog, folder or bag (small recordings and tests).
std::vector<RangeScan> readScans(const std::string& path, const ScanReaderOptions& options = {});

}  // namespace icrkit::reconstruction
