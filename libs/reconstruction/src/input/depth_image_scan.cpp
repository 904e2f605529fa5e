#include <icrkit/reconstruction/input/depth_image_scan.hpp>

#include "observation_scan.hpp"

#include <icrkit/core/error.hpp>

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace icrkit::reconstruction {

Eigen::Isometry3d opticalToSensorPose(const Eigen::Isometry3d& optical_pose) {
  Eigen::Isometry3d sensor = optical_pose;
  sensor.linear() = optical_pose.linear() * mrptSensorAxesInOptical();
  return sensor;
}

RangeScan scanFromDepthImage(const DepthImageView& image, const DepthImageMeta& meta, std::size_t index,
                             const std::string& source) {
  const std::string where = "scan " + std::to_string(index);
  if ((image.counts == nullptr) == (image.metres == nullptr))
    throw InputError(source, where, "expected one depth image: 16-bit counts or float metres");
  if (image.width <= 0 || image.height <= 0)
    throw InputError(source, where, "expected a depth image of at least 1x1 pixels");
  if (image.width != meta.intrinsics.width || image.height != meta.intrinsics.height)
    throw InputError(source, where,
                     "the depth image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " but its camera is " + std::to_string(meta.intrinsics.width) + "x" +
                         std::to_string(meta.intrinsics.height));
  const std::size_t stride = image.row_stride == 0 ? static_cast<std::size_t>(image.width) : image.row_stride;
  if (stride < static_cast<std::size_t>(image.width))
    throw InputError(source, where, "the row stride is shorter than a row");

  double unit = 0.0;
  if (image.counts) {
    if (!(image.depth_scale > 0) || !std::isfinite(image.depth_scale))
      throw InputError(source, where, "expected a depth scale (counts per metre) that is finite and > 0");
    // Single precision, as MRPT stores rangeUnits: a rawlog written from
    // these images then holds the very same ranges.
    unit = 1.0 / image.depth_scale;
  } else {
    float farthest = 0.0f;
    for (int r = 0; r < image.height; ++r) {
      const float* row = image.metres + static_cast<std::size_t>(r) * stride;
      for (int c = 0; c < image.width; ++c) {
        if (std::isinf(row[c]) && row[c] > 0)
          throw InputError(source, where + " pixel (" + std::to_string(r) + ", " + std::to_string(c) + ")",
                           "expected a finite depth in metres, or 0 / NaN for no return");
        if (row[c] > farthest) farthest = row[c];
      }
    }
    unit = std::max(kFloatDepthUnit, static_cast<double>(farthest) / 65535.0);
  }

  // The observation a depth camera driver would have recorded.
  mrpt::obs::CObservation3DRangeScan obs;
  obs.sensorLabel = meta.sensor_label;
  obs.timestamp = mrpt::Clock::fromDouble(meta.timestamp);
  obs.hasRangeImage = true;
  obs.rangeImage_setSize(image.height, image.width);
  obs.rangeUnits = static_cast<float>(unit);
  const double per_unit = 1.0 / static_cast<double>(obs.rangeUnits);
  for (int r = 0; r < image.height; ++r) {
    const std::size_t start = static_cast<std::size_t>(r) * stride;
    if (image.counts) {
      for (int c = 0; c < image.width; ++c) obs.rangeImage(r, c) = image.counts[start + c];
    } else {
      for (int c = 0; c < image.width; ++c) {
        const float d = image.metres[start + c];
        const double counts = d > 0 ? std::round(d * per_unit) : 0.0;
        obs.rangeImage(r, c) = static_cast<std::uint16_t>(std::min(counts, 65535.0));
      }
    }
  }
  obs.range_is_depth = true;
  obs.maxRange = static_cast<float>(meta.max_range);
  const CameraIntrinsics& k = meta.intrinsics;
  if (!(k.fx > 0) || !(k.fy > 0) || !std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) ||
      !std::isfinite(k.cy))
    throw InputError(source, where, "expected positive finite focal lengths and a finite principal point");
  obs.cameraParams = detail::toMrptCamera(k);
  obs.cameraParamsIntensity = obs.cameraParams;

  detail::ObservationConversion conversion;
  conversion.pose = &meta.sensor_pose;
  conversion.pose_normalised = meta.pose_normalised;
  conversion.unproject = meta.unproject;
  RangeScan scan = detail::scanFromObservation(obs, index, source, conversion);
  // As given, not through MRPT's 100 ns clock.
  scan.timestamp = meta.timestamp;
  return scan;
}

}  // namespace icrkit::reconstruction
