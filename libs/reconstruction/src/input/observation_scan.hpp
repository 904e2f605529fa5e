#pragma once
/// \file
/// The one conversion of an MRPT CObservation3DRangeScan into a RangeScan,
/// shared by the rawlog reader and the depth-image folder reader so that
/// both unproject their pixels by the same code (MRPT's unprojectInto).

#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <Eigen/Geometry>

#include <cstddef>
#include <string>

namespace icrkit::reconstruction::detail {

struct ObservationConversion {
  /// Replaces the observation's sensorPose (already a rotation); null: the
  /// observation's own pose, checked with orthonormaliseReadPose.
  const Eigen::Isometry3d* pose = nullptr;
  /// The replacement had to be normalised when it was read.
  bool pose_normalised = false;
  double rotation_tolerance = kReadRotationTolerance;
  bool unproject = true;
};

/// MRPT's camera (size, pinhole, plumb-bob distortion) of `intrinsics`.
mrpt::img::TCamera toMrptCamera(const CameraIntrinsics& intrinsics);

/// Checks and converts a loaded observation (images in memory). `source`
/// and "scan `index`" name it in the InputError thrown for inconsistent
/// sizes, non-positive focal lengths or units, or a pose that is not a
/// rotation. The observation's sensorPose is left as the scan uses it.
RangeScan scanFromObservation(mrpt::obs::CObservation3DRangeScan& obs, std::size_t index, const std::string& source,
                              const ObservationConversion& conversion);

}  // namespace icrkit::reconstruction::detail
