#pragma once
/// \file
/// Conversion between Eigen isometries and MRPT's CPose3D.

#include <Eigen/Geometry>
#include <mrpt/poses/CPose3D.h>

namespace icrkit {

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose);
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose);

}  // namespace icrkit
