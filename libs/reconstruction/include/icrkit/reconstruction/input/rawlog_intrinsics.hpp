#pragma once
/// \file
/// Writing calibrated intrinsics back into a recording: a copy of a rawlog
/// whose 3D scans carry the given camera model (`cameraParams` and
/// `cameraParamsIntensity`), everything else unchanged.

#include <icrkit/core/camera_intrinsics.hpp>

#include <cstddef>
#include <string>

namespace icrkit::reconstruction {

/// Streams `input` (plain or gzip, either layout) to `output` (gzip),
/// replacing the intrinsics of every CObservation3DRangeScan; returns how
/// many scans were changed. The camera size must match each scan's range
/// image. Written through a temporary file renamed into place; throws
/// InputError naming the file and the scan index otherwise.
std::size_t writeRawlogWithIntrinsics(const std::string& input, const std::string& output,
                                      const CameraIntrinsics& intrinsics);

}  // namespace icrkit::reconstruction
