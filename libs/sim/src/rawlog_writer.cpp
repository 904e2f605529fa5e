#include <icrkit/sim/rawlog_writer.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose_mrpt.hpp>

#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

namespace icrkit::sim {
namespace {

mrpt::img::TCamera cameraOf(const SensorModel& model) {
  const CameraIntrinsics& k = model.intrinsics;
  mrpt::img::TCamera camera;
  camera.ncols = static_cast<std::uint32_t>(k.width);
  camera.nrows = static_cast<std::uint32_t>(k.height);
  camera.setIntrinsicParamsFromValues(k.fx, k.fy, k.cx, k.cy);
  camera.setDistortionPlumbBob(k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3], k.distortion[4]);
  return camera;
}

mrpt::obs::CObservation3DRangeScan observationOf(const SensorModel& model, const SimulatedScan& scan, const View& view) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.sensorLabel = model.type == SensorType::Kinect ? "KINECT" : "SR4000";
  obs.timestamp = mrpt::Clock::fromDouble(kRawlogEpoch + view.timestamp);
  obs.sensorPose = toCPose3D(mrptSensorPose(view.reported_camera));
  obs.cameraParams = cameraOf(model);
  obs.cameraParamsIntensity = obs.cameraParams;  // registered: same pixels
  obs.maxRange = static_cast<float>(model.max_range);
  obs.range_is_depth = model.range_is_depth;
  obs.rangeUnits = static_cast<float>(model.range_units);

  obs.hasRangeImage = true;
  obs.rangeImage_setSize(scan.height, scan.width);
  for (int r = 0; r < scan.height; ++r)
    for (int c = 0; c < scan.width; ++c) {
      const double range = scan.range[static_cast<std::size_t>(r) * scan.width + c];
      const double counts = std::round(range / model.range_units);
      obs.rangeImage(r, c) = (range > 0 && counts <= 65535.0) ? static_cast<std::uint16_t>(counts) : 0;
    }

  if (!scan.colour.empty()) {
    obs.hasIntensityImage = true;
    obs.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
    obs.intensityImage = mrpt::img::CImage(scan.width, scan.height, mrpt::img::CH_RGB);
    for (int r = 0; r < scan.height; ++r) {
      auto* row = obs.intensityImage.ptrLine<std::uint8_t>(static_cast<unsigned>(r));
      for (int c = 0; c < scan.width; ++c) {
        const Colour& rgb = scan.colour[static_cast<std::size_t>(r) * scan.width + c];
        // CImage keeps colour pixels in OpenCV's BGR order.
        row[3 * c + 0] = rgb[2];
        row[3 * c + 1] = rgb[1];
        row[3 * c + 2] = rgb[0];
      }
    }
  } else if (!scan.intensity.empty()) {
    obs.hasIntensityImage = true;
    obs.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_IR;
    obs.intensityImage = mrpt::img::CImage(scan.width, scan.height, mrpt::img::CH_GRAY);
    for (int r = 0; r < scan.height; ++r) {
      auto* row = obs.intensityImage.ptrLine<std::uint8_t>(static_cast<unsigned>(r));
      for (int c = 0; c < scan.width; ++c) row[c] = scan.intensity[static_cast<std::size_t>(r) * scan.width + c];
    }
  }
  if (!scan.confidence.empty()) {
    obs.hasConfidenceImage = true;
    obs.confidenceImage = mrpt::img::CImage(scan.width, scan.height, mrpt::img::CH_GRAY);
    for (int r = 0; r < scan.height; ++r) {
      auto* row = obs.confidenceImage.ptrLine<std::uint8_t>(static_cast<unsigned>(r));
      for (int c = 0; c < scan.width; ++c) row[c] = scan.confidence[static_cast<std::size_t>(r) * scan.width + c];
    }
  }
  return obs;
}

}  // namespace

Eigen::Matrix3d mrptSensorToOptical() {
  Eigen::Matrix3d r;
  // Columns: MRPT's x (forward), y (left), z (up) in optical coordinates.
  r << 0, -1, 0,  //
      0, 0, -1,   //
      1, 0, 0;
  return r;
}

Eigen::Isometry3d mrptSensorPose(const Eigen::Isometry3d& optical_in_object) {
  Eigen::Isometry3d pose = optical_in_object;
  pose.linear() = optical_in_object.linear() * mrptSensorToOptical();
  return pose;
}

void writeRawlog(const std::string& path, const SensorModel& model, const std::vector<SimulatedScan>& scans,
                 const std::vector<View>& views) {
  if (scans.size() != views.size())
    throw InputError(path, "", "internal: " + std::to_string(scans.size()) + " scans for " +
                                   std::to_string(views.size()) + " views");
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const SimulatedScan& s = scans[i];
    const auto pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
    if (s.width != model.intrinsics.width || s.height != model.intrinsics.height || s.range.size() != pixels)
      throw InputError(path, "scan " + std::to_string(i), "image size does not match the sensor model");
  }
  const std::filesystem::path target(path);
  std::filesystem::path temporary = target;
  temporary += ".tmp";
  {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(temporary.string(), 1))
      throw InputError(path, "", "cannot write (is the folder there and writable?)");
    auto archive = mrpt::serialization::archiveFrom(out);
    for (std::size_t i = 0; i < scans.size(); ++i) archive << observationOf(model, scans[i], views[i]);
    out.close();
  }
  std::error_code error;
  std::filesystem::rename(temporary, target, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw InputError(path, "", "cannot move the finished rawlog into place");
  }
}

}  // namespace icrkit::sim
