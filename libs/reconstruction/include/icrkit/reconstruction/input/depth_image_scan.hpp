#pragma once
/// \file
/// A depth image held in memory (a camera driver's frame, a ROS message, a
/// NumPy array) turned into the RangeScan every reader gives: the image goes
/// into an MRPT CObservation3DRangeScan and through the rawlog reader's one
/// conversion, so its points are MRPT's unprojection exactly as for a rawlog
/// or a TUM folder holding the same pixels.

#include <icrkit/core/camera_intrinsics.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <string>

namespace icrkit::reconstruction {

/// A view of one depth image (not owned). Exactly one of `counts` and
/// `metres` is set; 0 (or NaN, or a negative value) means no return.
struct DepthImageView {
  int width = 0, height = 0;
  /// 16-bit depth counts and how many make a metre (1000: millimetres, as
  /// ROS's 16UC1 and most drivers; 5000: TUM RGB-D).
  const std::uint16_t* counts = nullptr;
  double depth_scale = 1000.0;
  /// Depth in metres (ROS's 32FC1). Stored as MRPT does, in 16-bit units of
  /// kFloatDepthUnit (0.1 mm) up to 6.5 m, coarser only for farther images.
  const float* metres = nullptr;
  /// Elements from one row's start to the next's; 0: `width` (packed).
  std::size_t row_stride = 0;
};

/// The unit (metres per count) a float depth image is stored in.
inline constexpr double kFloatDepthUnit = 1e-4;

/// Where and when the image was taken.
struct DepthImageMeta {
  CameraIntrinsics intrinsics;  ///< width and height must match the image's
  /// The camera's pose in the object frame in MRPT's sensor axes (+x along
  /// the optical axis, +y left, +z up): opticalToSensorPose() of a camera
  /// pose in the optical frame (x right, y down, z forward; ROS, TUM).
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  bool pose_normalised = false;  ///< the pose had to be made a rotation when read
  double timestamp = 0.0;        ///< seconds
  double max_range = 0.0;        ///< metres; 0: not given
  std::string sensor_label = "DEPTH";
  bool unproject = true;  ///< compute the scan's points
};

/// A camera pose in the optical frame (camera-to-object) in MRPT's sensor axes.
Eigen::Isometry3d opticalToSensorPose(const Eigen::Isometry3d& optical_pose);

/// Converts one image. `source` and "scan `index`" name it in the
/// InputError thrown for a size that does not match the intrinsics, both
/// or neither of counts/metres, a depth scale that is not finite and > 0,
/// non-positive focal lengths, or an infinite depth.
RangeScan scanFromDepthImage(const DepthImageView& image, const DepthImageMeta& meta, std::size_t index,
                             const std::string& source);

}  // namespace icrkit::reconstruction
