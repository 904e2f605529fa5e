#pragma once
/// \file
/// Registration error of estimated sensor poses against ground truth.
///
/// A reconstruction fixes its frame only up to what the robot reported, so
/// two figures are given per scan: as estimated, and after the rigid
/// transform that best fits the estimated sensor positions to the true ones
/// (Horn/Umeyama without scale, the usual absolute-trajectory-error
/// alignment). Each is measured at the sensor (the pose's translation) and
/// at the object (how far the scan's points at `object_point` move: what a
/// fused model sees; the sensor sits ~0.7 m away, where a 0.05 degree
/// rotation alone moves it by 0.6 mm).

#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

struct PoseErrorSeries {
  std::vector<double> sensor_translation_m;  ///< |t_est - t_true| of the sensor origin
  std::vector<double> object_translation_m;  ///< displacement of the object point
  std::vector<double> rotation_rad;          ///< angle of R_true^T R_est
  double median_sensor_translation_m = 0.0, max_sensor_translation_m = 0.0;
  double median_object_translation_m = 0.0, max_object_translation_m = 0.0;
  double median_rotation_rad = 0.0, max_rotation_rad = 0.0;
};

struct TrajectoryError {
  PoseErrorSeries raw;      ///< as estimated
  PoseErrorSeries aligned;  ///< after the best-fit rigid alignment
  /// The alignment (estimated frame -> true frame).
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
};

/// Throws InputError when the two lists differ in length or are empty.
/// With fewer than three poses, or collinear positions, the alignment
/// falls back to the one that maps the first estimated pose onto the first
/// true pose.
TrajectoryError trajectoryError(const std::vector<Eigen::Isometry3d>& estimated,
                                const std::vector<Eigen::Isometry3d>& truth, const Eigen::Vector3d& object_point);

}  // namespace icrkit::reconstruction
