#pragma once
/// \file
/// Range scans built in the test from a ray-cast function, with known answers.

#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <functional>

namespace icrkit::reconstruction::testing_support {

/// A pinhole camera at `eye` looking at `target` (object frame, z up).
inline Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d optical;
  optical << right, down, forward;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = optical * mrptSensorAxesInOptical();
  pose.translation() = eye;
  return pose;
}

/// An empty depth scan (range_is_depth) of w x h pixels, focal length f.
inline RangeScan blankScan(int w, int h, double f, const Eigen::Isometry3d& pose) {
  RangeScan scan;
  scan.width = w;
  scan.height = h;
  scan.camera.width = w;
  scan.camera.height = h;
  scan.camera.fx = scan.camera.fy = f;
  scan.camera.cx = (w - 1) / 2.0;
  scan.camera.cy = (h - 1) / 2.0;
  scan.camera_intensity = scan.camera;
  scan.sensor_pose = pose;
  scan.max_range = 10.0;
  scan.range.assign(static_cast<std::size_t>(w) * h, 0.0f);
  return scan;
}

/// Fills `points`/`pixels` from the range image (pinhole, no distortion).
inline void unprojectPinhole(RangeScan& scan) {
  scan.points.clear();
  scan.pixels.clear();
  const Eigen::Matrix3d axes_t = mrptSensorAxesInOptical().transpose();
  for (int r = 0; r < scan.height; ++r)
    for (int c = 0; c < scan.width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * scan.width + c;
      if (!(scan.range[i] > 0)) continue;
      scan.points.push_back(scan.sensor_pose * (axes_t * opticalPoint(scan, r, c, scan.range[i])));
      scan.pixels.push_back(static_cast<std::uint32_t>(i));
    }
}

/// Casts every pixel's ray: `hit(origin, direction)` returns the distance
/// along the unit direction (object frame), <= 0 for no hit. Stores depths.
inline void castRays(RangeScan& scan, const std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)>& hit) {
  const Eigen::Matrix3d optical_to_object = scan.sensor_pose.linear() * mrptSensorAxesInOptical().transpose();
  for (int r = 0; r < scan.height; ++r)
    for (int c = 0; c < scan.width; ++c) {
      const Eigen::Vector3d ray_optical = opticalPoint(scan, r, c, 1.0);  // z = 1
      const double t = hit(scan.sensor_pose.translation(), (optical_to_object * ray_optical).normalized());
      scan.range[static_cast<std::size_t>(r) * scan.width + c] =
          t > 0 ? static_cast<float>(t / ray_optical.norm()) : 0.0f;
    }
  unprojectPinhole(scan);
}

}  // namespace icrkit::reconstruction::testing_support
