#pragma once
// What a registration can observe. A surface of revolution (a cup, a
// bottle) does not fix the rotation about its axis, a plane does not fix
// sliding along it, and an NDT score still "sees" those motions through the
// edges of a partial view, so the optimiser wanders. The registration's
// correction is kept only in the directions the surface constrains
// (solution remapping, Zhang, Kaess and Singh, ICRA 2016), and the pose
// graph edge gets no information in the others, so that the robot's poses
// decide them.
//
// Conventions: x = [t; phi] is a left perturbation T -> Exp(x) T in the
// target frame (the NDT's parameters at x = 0), tangent order [rho; theta]
// like pose_graph.hpp.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace icrkit::reconstruction {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

struct Observability {
  /// Projects a left perturbation onto its observed part.
  Matrix6 projector = Matrix6::Identity();
  /// Directions left out (0 = fully constrained).
  int degenerate_directions = 0;
  /// Smallest eigenvalue / largest (scaled as below): how weakly the
  /// registration's least constrained direction is observed.
  double weakest_ratio = 1.0;
};

/// Where a surface constrains a registration: the eigen-directions of the
/// point-to-plane stability matrix sum [n; (p - c) x n / s][...]^T, c the
/// points' centroid and s their RMS radius (so that rotations and
/// translations compare in metres), whose eigenvalue is at least `ratio`
/// times the largest (Gelfand, Ikemoto, Rusinkiewicz and Levoy, "Geometrically stable
/// sampling for the ICP algorithm", 3DIM 2003). It depends only on the
/// local shape, so the edges of a partial view, which give an NDT score a
/// spurious grip (a cup's rotation about its own axis), do not count.
/// `normals` need no consistent sign; zero normals are ignored.
Observability surfaceObservability(const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& normals, double ratio);

/// SE(3) adjoint for [rho; theta]: T Exp(xi) T^-1 = Exp(Ad(T) xi).
Matrix6 adjoint(const Eigen::Isometry3d& t);

/// First-order log / exp of a small rigid motion as [t; rotation vector].
Vector6 smallMotionLog(const Eigen::Isometry3d& t);
Eigen::Isometry3d smallMotionExp(const Vector6& x);

}  // namespace icrkit::reconstruction
