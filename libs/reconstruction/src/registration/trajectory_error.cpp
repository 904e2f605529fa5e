#include <icrkit/reconstruction/registration/trajectory_error.hpp>

#include <icrkit/core/error.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <string>

namespace icrkit::reconstruction {

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  double m = values[mid];
  if (values.size() % 2 == 0) m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

PoseErrorSeries series(const std::vector<Eigen::Isometry3d>& estimated, const std::vector<Eigen::Isometry3d>& truth,
                       const Eigen::Isometry3d& alignment, const Eigen::Vector3d& object_point) {
  PoseErrorSeries s;
  for (std::size_t i = 0; i < estimated.size(); ++i) {
    const Eigen::Isometry3d est = alignment * estimated[i];
    s.sensor_translation_m.push_back((est.translation() - truth[i].translation()).norm());
    // A scan point at the object, placed by the estimate instead of the truth.
    const Eigen::Isometry3d moved = est * truth[i].inverse();
    s.object_translation_m.push_back((moved * object_point - object_point).norm());
    s.rotation_rad.push_back(Eigen::AngleAxisd(truth[i].rotation().transpose() * est.rotation()).angle());
  }
  auto maxOf = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  s.median_sensor_translation_m = median(s.sensor_translation_m);
  s.max_sensor_translation_m = maxOf(s.sensor_translation_m);
  s.median_object_translation_m = median(s.object_translation_m);
  s.max_object_translation_m = maxOf(s.object_translation_m);
  s.median_rotation_rad = median(s.rotation_rad);
  s.max_rotation_rad = maxOf(s.rotation_rad);
  return s;
}

}  // namespace

TrajectoryError trajectoryError(const std::vector<Eigen::Isometry3d>& estimated,
                                const std::vector<Eigen::Isometry3d>& truth, const Eigen::Vector3d& object_point) {
  if (estimated.empty() || estimated.size() != truth.size())
    throw InputError("ground truth", "", "expected one true pose per scan (" + std::to_string(estimated.size()) +
                                             "), got " + std::to_string(truth.size()));
  TrajectoryError error;
  error.raw = series(estimated, truth, Eigen::Isometry3d::Identity(), object_point);

  Eigen::Isometry3d alignment = truth.front() * estimated.front().inverse();
  if (estimated.size() >= 3) {
    Eigen::Matrix3Xd from(3, estimated.size()), to(3, estimated.size());
    for (std::size_t i = 0; i < estimated.size(); ++i) {
      from.col(static_cast<Eigen::Index>(i)) = estimated[i].translation();
      to.col(static_cast<Eigen::Index>(i)) = truth[i].translation();
    }
    // Positions spread in at least two directions fix a rotation.
    const Eigen::Matrix3Xd centred = from.colwise() - from.rowwise().mean();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread(centred * centred.transpose());
    if (spread.eigenvalues()(1) > 1e-9 * std::max(1.0, spread.eigenvalues()(2))) {
      const Eigen::Matrix4d m = Eigen::umeyama(from, to, false);
      alignment.matrix() = m;
    }
  }
  error.alignment = alignment;
  error.aligned = series(estimated, truth, alignment, object_point);
  return error;
}

}  // namespace icrkit::reconstruction
