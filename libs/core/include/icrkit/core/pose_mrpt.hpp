#pragma once
/// \file
/// Conversion between Eigen isometries and MRPT's CPose3D, for the code that
/// reads or writes MRPT rawlogs (the reconstruction's reader, the simulator's
/// writer). Header-only on purpose: icrkit::core does not link MRPT, so a
/// target that includes this header links mrpt::poses itself.

#include <Eigen/Geometry>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

namespace icrkit {

inline Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  const auto rotation = pose.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) result.linear()(r, c) = rotation(r, c);
  result.translation() = Eigen::Vector3d(pose.x(), pose.y(), pose.z());
  return result;
}

inline mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose) {
  mrpt::math::CMatrixDouble33 rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation(r, c) = pose.linear()(r, c);
  mrpt::math::CVectorFixedDouble<3> translation;
  for (int k = 0; k < 3; ++k) translation[k] = pose.translation()[k];
  return mrpt::poses::CPose3D(rotation, translation);
}

}  // namespace icrkit
