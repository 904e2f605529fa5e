#pragma once
/// \file
/// Closed-form eigen-decomposition of a symmetric 3x3 matrix (a covariance).

#include <Eigen/Core>

namespace icrkit::ndt {

struct SymmetricEigen3 {
  Eigen::Vector3d values;   ///< l1 >= l2 >= l3
  Eigen::Matrix3d vectors;  ///< orthonormal columns v1, v2, v3 matching `values`
};

/// Eigenvalues by the trigonometric solution of the characteristic cubic;
/// the vector of the better-separated extreme eigenvalue from cross products
/// of the rows of (A - l I), the other two from the 2x2 problem orthogonal
/// to it; eigenvalues refined as Rayleigh quotients. No iteration, no
/// allocation.
SymmetricEigen3 eigenSymmetric3(const Eigen::Matrix3d& a);

}  // namespace icrkit::ndt
