#pragma once
/// \file
/// Streamed reading of MRPT rawlogs of `CObservation3DRangeScan` (the
/// recording contract of docs/rawlog.md): one scan at a time, so that a
/// recording of hundreds of Kinect frames never sits in memory at once.
///
/// Plain and gzip files are read alike (zlib passes plain files through);
/// both the observation-only layout and MRPT's action/sensory-frame layout
/// are understood. Other observations and actions are skipped.

#include <icrkit/core/camera_intrinsics.hpp>
#include <icrkit/core/pose.hpp>

#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// An 8-bit image, row-major; `channels` is 1 (grey, amplitude, confidence)
/// or 3 (RGB order, converted from MRPT's BGR).
struct Image8 {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> data;
  bool empty() const { return data.empty(); }
};

/// One range scan in metres with its points in the object frame.
struct RangeScan {
  std::size_t index = 0;      ///< 0-based among the 3D scans of the rawlog (a folder's listed frames)
  double timestamp = 0.0;     ///< seconds since 1970 (UTC)
  std::string sensor_label;
  /// Sensor pose in the object frame, MRPT's sensor axes (+x forward, +y
  /// left, +z up); from the rawlog or the TUM override.
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  /// The pose as read was not exactly a rotation (a matrix off by more than
  /// double rounding, a quaternion off unit length) and was projected onto
  /// the nearest one (core/pose.hpp, orthonormaliseReadPose).
  bool pose_orthonormalised = false;
  /// true: values are depths along the optical axis; false: distances along the pixel's ray.
  bool range_is_depth = true;
  double max_range = 0.0;  ///< metres, the sensor's nominal maximum
  int width = 0, height = 0;
  /// Row-major, metres, 0 = no return (or removed by a filter).
  std::vector<float> range;
  CameraIntrinsics camera;            ///< of the range image (core/camera_intrinsics.hpp)
  CameraIntrinsics camera_intensity;  ///< of the intensity image (registered: usually the same)
  Image8 intensity;              ///< colour (Kinect) or amplitude (ToF); empty when absent
  bool intensity_is_ir = false;  ///< MRPT's CH_IR: an amplitude image rather than colour
  Image8 confidence;             ///< empty when absent
  /// The valid pixels unprojected by MRPT (unprojectInto with the sensor
  /// pose) in the object frame, with each one's pixel (row * width + col).
  std::vector<Eigen::Vector3d> points;
  std::vector<std::uint32_t> pixels;

  std::size_t validPixels() const;
  /// Drops the points whose pixel no longer has a range (after a filter
  /// set it to 0); returns how many were dropped.
  std::size_t dropInvalidPoints();
};

struct RawlogReaderOptions {
  /// A TUM trajectory (`timestamp tx ty tz qx qy qz qw`, MRPT sensor axes,
  /// object frame) whose i-th pose replaces the i-th scan's sensorPose
  /// (matched by order, not by time stamp). Empty: use the rawlog's poses.
  std::string pose_file;
  /// Folder of externally stored images; empty: `<rawlog name without
  /// extension>_Images` next to the rawlog (MRPT's convention).
  std::string images_folder;
  /// Compute `points` and `pixels` (skip for a pass over the images only;
  /// filterCropBox and removeSupportPlane need the points).
  bool unproject = true;
  /// How far (max |R^T R - I|) a `sensorPose` rotation may be from
  /// orthonormal and still be projected onto the nearest rotation; beyond:
  /// InputError naming the scan.
  double rotation_tolerance = kReadRotationTolerance;
};

/// Reads the 3D range scans of a rawlog one at a time:
///
///     RawlogReader reader(path);
///     while (auto scan = reader.next()) { ... }
///
/// Throws InputError (naming the file and the scan index) for a missing or
/// truncated file, a rawlog without any 3D scan, a scan without a range
/// image, inconsistent image sizes, a `sensorPose` that is not a rotation
/// (beyond `rotation_tolerance`), or too few poses in the pose file.
class RawlogReader {
public:
  explicit RawlogReader(const std::string& path, RawlogReaderOptions options = {});
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// The next scan, or nothing at the end of the file.
  std::optional<RangeScan> next();
  /// Scans returned so far.
  std::size_t scansRead() const;
  const std::string& path() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads every scan (convenience for small recordings and tests).
std::vector<RangeScan> readAllScans(const std::string& path, const RawlogReaderOptions& options = {});

/// The point of pixel (row, col) at `range` metres (a depth or a ray
/// length, as the scan says) in the sensor's optical frame (x right, y
/// down, z forward); pinhole model without distortion, like MRPT's
/// unprojection. Shared by the filters.
Eigen::Vector3d opticalPoint(const RangeScan& scan, int row, int col, double range);

/// MRPT's sensor axes in optical coordinates (columns: forward, left, up).
Eigen::Matrix3d mrptSensorAxesInOptical();

}  // namespace icrkit::reconstruction
