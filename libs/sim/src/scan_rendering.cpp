#include "scan_rendering.hpp"

#include <icrkit/core/error.hpp>

#include "lens_distortion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace icrkit::sim {

SimulatedScan simulateScan(const RayCaster& scene, const SceneAppearance& appearance,
                           const Eigen::Isometry3d& camera_in_scene, const SensorModel& model, std::uint64_t seed) {
  checkSensorModel(model);
  if (!camera_in_scene.matrix().allFinite())
    throw InputError("camera pose", "", "the camera pose must be finite");

  // Defaults, and reflectivities kept physical whatever the callback says.
  auto colour = appearance.colour ? appearance.colour
                                : std::function<Colour(int, const Eigen::Vector3d&)>(
                                      [](int, const Eigen::Vector3d&) { return Colour{128, 128, 128}; });
  std::function<double(int, const Eigen::Vector3d&)> reflectivity;
  if (appearance.reflectivity) {
    reflectivity = [f = appearance.reflectivity](int face, const Eigen::Vector3d& point) {
      const double value = f(face, point);
      return std::isfinite(value) ? std::clamp(value, 0.0, 1.0) : 0.0;
    };
  } else {
    reflectivity = [](int, const Eigen::Vector3d&) { return 0.6; };
  }
  const RenderContext context{scene, model, CameraFrame(camera_in_scene), std::move(colour), std::move(reflectivity),
                              seed};

  SimulatedScan scan;
  scan.width = model.intrinsics.width;
  scan.height = model.intrinsics.height;
  const std::size_t n = static_cast<std::size_t>(scan.width) * static_cast<std::size_t>(scan.height);
  scan.range.assign(n, 0.0f);
  scan.intensity.assign(n, 0);
  scan.confidence.assign(n, 0);
  scan.true_range.assign(n, 0.0f);
  scan.true_face.assign(n, -1);
  if (model.type == SensorType::Kinect) {
    scan.colour.assign(n, Colour{0, 0, 0});
    renderKinect(context, scan);
  } else {
    renderSr4000(context, scan);
  }
  return scan;
}

PointCloud unprojectScan(const SimulatedScan& scan, const SensorModel& model, RangeSource source) {
  checkSensorModel(model);
  const std::size_t n = static_cast<std::size_t>(std::max(scan.width, 0)) * static_cast<std::size_t>(std::max(scan.height, 0));
  if (scan.width != model.intrinsics.width || scan.height != model.intrinsics.height)
    throw InputError("scan", "", "the scan is " + std::to_string(scan.width) + " x " + std::to_string(scan.height) +
                                     " pixels, the sensor model " + std::to_string(model.intrinsics.width) + " x " +
                                     std::to_string(model.intrinsics.height));
  const std::vector<float>& ranges = source == RangeSource::Measured ? scan.range : scan.true_range;
  if (ranges.size() != n || (!scan.colour.empty() && scan.colour.size() != n) ||
      (!scan.intensity.empty() && scan.intensity.size() != n) || (!scan.confidence.empty() && scan.confidence.size() != n))
    throw InputError("scan", "", "image arrays do not hold width x height = " + std::to_string(n) + " pixels");

  PointCloud cloud;
  std::vector<double> pixel, intensity, confidence;
  for (int row = 0; row < scan.height; ++row) {
    for (int column = 0; column < scan.width; ++column) {
      const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(scan.width) + static_cast<std::size_t>(column);
      const double range = ranges[i];
      if (!(range > 0.0)) continue;
      const Eigen::Vector3d direction = pixelDirection(model.intrinsics, column, row);
      if (!direction.allFinite()) continue;
      // Depth scales the (x, y, 1) direction; a ray range its unit vector.
      cloud.positions.push_back(model.range_is_depth ? Eigen::Vector3d(range * direction)
                                                     : Eigen::Vector3d(range * direction.normalized()));
      if (!scan.colour.empty()) cloud.colours.push_back(scan.colour[i]);
      pixel.push_back(static_cast<double>(i));
      intensity.push_back(scan.intensity.empty() ? 0.0 : scan.intensity[i]);
      confidence.push_back(scan.confidence.empty() ? 0.0 : scan.confidence[i]);
    }
  }
  cloud.attributes.add("pixel", ScalarType::UInt32, std::move(pixel));
  cloud.attributes.add("intensity", ScalarType::UInt8, std::move(intensity));
  cloud.attributes.add("confidence", ScalarType::UInt8, std::move(confidence));
  return cloud;
}

}  // namespace icrkit::sim
