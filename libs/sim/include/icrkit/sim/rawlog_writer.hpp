#pragma once
/// \file
/// Simulated scans written as an MRPT rawlog of CObservation3DRangeScan, the
/// format the reconstruction reads for real recordings too. The convention
/// (fields, units, axes, poses) is docs/rawlog.md.

#include <icrkit/sim/acquisition.hpp>
#include <icrkit/sim/range_sensor.hpp>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace icrkit::sim {

/// The rotation from MRPT's sensor axes (x forward, y left, z up) to the
/// optical axes (x right, y down, z forward): sensorPose = optical pose * this.
Eigen::Matrix3d mrptSensorToOptical();
/// The pose of MRPT's sensor axes for a given optical-frame pose.
Eigen::Isometry3d mrptSensorPose(const Eigen::Isometry3d& optical_in_object);

/// Epoch of the first view's timestamp (seconds since 1970, UTC): fixed, so
/// that the same simulation writes the same bytes.
constexpr double kRawlogEpoch = 1335830400.0;  // 2012-05-01

/// Writes one observation per scan (observation-only layout, gzip level 1)
/// to `path` through a temporary file renamed into place: `rangeImage` in
/// the model's `range_units`, `range_is_depth`, `cameraParams` and
/// `cameraParamsIntensity` (the model's intrinsics and plumb-bob
/// distortion), the colour (Kinect, CH_VISIBLE) or amplitude (SR4000, CH_IR)
/// image, the confidence image, `sensorPose` = views[i].reported_camera in
/// MRPT's sensor axes, timestamps kRawlogEpoch + views[i].timestamp, and the
/// sensor label "KINECT" or "SR4000". Ranges beyond what 16 bits hold are
/// written as 0 (no return). Throws InputError when the file cannot be
/// written (nothing is left behind) or the sizes disagree.
void writeRawlog(const std::string& path, const SensorModel& model, const std::vector<SimulatedScan>& scans,
                 const std::vector<View>& views);

}  // namespace icrkit::sim
