#include <icrkit/reconstruction/input/up_axis.hpp>

#include <cmath>

namespace icrkit::reconstruction {

Eigen::Vector3d estimateUpAxis(const std::vector<Eigen::Isometry3d>& sensor_poses, double z_preference) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& pose : sensor_poses) {
    const Eigen::Matrix3d r = pose.rotation();
    sum += r.col(2).normalized() - r.col(0).normalized();
  }
  // Views that cancel out (half of them upside down) say nothing.
  if (!sum.allFinite() || sum.norm() < 1e-6 * static_cast<double>(sensor_poses.size() + 1))
    return Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d direction = sum.normalized();
  if (direction.z() >= std::cos(z_preference)) return Eigen::Vector3d::UnitZ();
  Eigen::Index axis = 0;
  direction.cwiseAbs().maxCoeff(&axis);
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  up[axis] = direction[axis] < 0.0 ? -1.0 : 1.0;
  return up;
}

}  // namespace icrkit::reconstruction
