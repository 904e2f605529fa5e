#pragma once
/// \file
/// 3D pose graph optimisation: scan poses (nodes) tied by relative-pose
/// measurements (edges, e.g. NDT registrations between overlapping scans),
/// solved by Gauss-Newton / Levenberg-Marquardt on SE(3) with a sparse
/// Cholesky factorisation (CHOLMOD). See docs/pose_graph.md.
///
/// Conventions. A pose T maps scan coordinates into the model frame. The
/// measurement T_ij of an edge (i, j) is the pose of scan j in scan i's
/// frame, so without error T_j = T_i T_ij. Tangent vectors are 6-vectors
/// [rho; theta]: a translation in metres and a rotation vector in radians,
/// applied on the right (in the scan's own frame, see `poseGraphRetract`).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct PoseGraphEdge {
  std::size_t from = 0;  ///< node i
  std::size_t to = 0;    ///< node j (!= i)
  /// T_ij: the pose of node j in node i's frame.
  Eigen::Isometry3d measurement = Eigen::Isometry3d::Identity();
  /// Inverse covariance of the error [rho; theta] (1/m^2 for the
  /// translation block, 1/rad^2 for the rotation block); symmetric
  /// positive definite. The identity weights 1 m like 1 rad: pass e.g.
  /// `poseGraphInformation(0.002, 0.003)` or a registration's Hessian.
  Matrix6d information = Matrix6d::Identity();
  /// Whether the robust kernel (if any) applies to this edge. Odometry
  /// edges that cannot be wrong may opt out; loop closures should not.
  bool robust = true;
};

struct PoseGraph {
  /// Initial poses (scan -> model); the optimiser starts from these.
  std::vector<Eigen::Isometry3d> poses;
  std::vector<PoseGraphEdge> edges;
  /// Nodes held at their initial pose (at least one: a pose graph only
  /// knows relative poses). Every other node must be connected to one of
  /// them through edges.
  std::vector<std::size_t> fixed = {0};
};

enum class RobustKernel {
  None,    ///< plain least squares
  Huber,   ///< quadratic up to `kernel_width`, linear beyond
  Cauchy,  ///< logarithmic beyond `kernel_width`: wrong loop closures lose nearly all weight
};

struct PoseGraphParameters {
  /// Upper bound on the number of linearisations (accepted or rejected
  /// Levenberg-Marquardt steps alike) of each stage: the robust kernel's
  /// warm start and each of its annealing stages get this many each.
  int max_iterations = 100;
  /// Levenberg-Marquardt damping (H + lambda diag(H)); false = plain
  /// Gauss-Newton (every step taken, diverges more easily from a poor start).
  bool levenberg_marquardt = true;
  /// Initial damping factor lambda (dimensionless).
  double initial_lambda = 1e-5;
  /// Stop when the largest component of an accepted update is below this
  /// (metres and radians).
  double update_tolerance = 1e-10;
  /// Stop when an accepted step lowers the cost by less than this fraction.
  double relative_decrease_tolerance = 1e-12;
  RobustKernel kernel = RobustKernel::None;
  /// Kernel width on the Mahalanobis distance sqrt(e^T Omega e)
  /// (dimensionless, "sigmas"). 2.0 keeps ~99 % of inliers with a 6-DoF
  /// error quadratic when the information matrices are honest.
  double kernel_width = 2.0;
  /// With a kernel: first converge without it, then with it. From a
  /// drifted start a correct loop closure is as far off as a wrong one, and
  /// a kernel applied at once would discard both (see docs/pose_graph.md).
  bool robust_warm_start = true;
  /// After the warm start, the kernel width starts at the largest residual
  /// (in sigmas) and shrinks by this factor per stage down to
  /// `kernel_width`, each stage solved to convergence (graduated
  /// non-convexity). <= 1: the final width at once.
  double kernel_annealing = 2.0;
};

struct PoseGraphReport {
  int iterations = 0;         ///< linearisations done
  int accepted_steps = 0;     ///< steps that lowered the cost
  double initial_chi2 = 0.0;  ///< sum of e^T Omega e at the initial poses
  double final_chi2 = 0.0;    ///< the same at the returned poses
  double initial_cost = 0.0;  ///< the robust cost (= chi2 without a kernel)
  double final_cost = 0.0;
  bool converged = false;  ///< a tolerance was met (not the iteration limit)
  std::size_t free_nodes = 0;
  std::size_t nonzeros = 0;         ///< stored entries of the upper triangle of H
  std::size_t factor_nonzeros = 0;  ///< entries of the Cholesky factor (fill-reducing order applied)
  bool supernodal = false;          ///< CHOLMOD's choice of factor type
  double time_ms = 0.0;             ///< wall-clock time, setup included
  /// Per edge, the final robust weight (1 = full; < 1 down-weighted).
  std::vector<double> edge_weights;
};

struct PoseGraphResult {
  std::vector<Eigen::Isometry3d> poses;  ///< same order as the input; fixed ones unchanged
  PoseGraphReport report;
};

/// Optimises the free poses. Throws InputError ("pose graph") for an edge
/// to a missing node or to itself, a non-finite pose or measurement, an
/// information matrix that is not symmetric positive definite, no fixed
/// node, a fixed index out of range, a node not connected to any fixed
/// node, or a parameter out of range. Deterministic: the same input gives
/// bit-identical output.
PoseGraphResult optimisePoseGraph(const PoseGraph& graph, const PoseGraphParameters& params = {});

/// Diagonal information for standard deviations `sigma_translation` (metres)
/// and `sigma_rotation` (radians), both > 0.
Matrix6d poseGraphInformation(double sigma_translation, double sigma_rotation);

/// T (+) delta = T * [Exp(theta), rho]: the update applied in the node's own
/// frame.
Eigen::Isometry3d poseGraphRetract(const Eigen::Isometry3d& pose, const Vector6d& delta);

/// The error of an edge: with E = T_ij^-1 T_i^-1 T_j, [translation(E);
/// Log(rotation(E))]. Optionally the analytic Jacobians d e / d delta_i and
/// d e / d delta_j for right perturbations (`poseGraphRetract`).
Vector6d poseGraphEdgeError(const Eigen::Isometry3d& pose_i, const Eigen::Isometry3d& pose_j,
                            const Eigen::Isometry3d& measurement, Matrix6d* jacobian_i = nullptr,
                            Matrix6d* jacobian_j = nullptr);

}  // namespace icrkit::reconstruction
