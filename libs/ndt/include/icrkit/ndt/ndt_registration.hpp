#pragma once
/// \file
/// Point-to-distribution 3D-NDT registration (Magnusson, "The Three-
/// Dimensional Normal-Distributions Transform", 2009, chapter 6).
///
/// The target cloud is summarised by a voxel grid of Gaussians (one per cell
/// with enough points). A source point x' = T(p) - mu scores
/// -d1 exp(-d2/2 x'^T Sigma^-1 x') against each Gaussian it is looked up in
/// (the Gaussian-plus-uniform outlier mixture, fitted by a Gaussian: Eq. 6.8);
/// Newton steps with a More-Thuente line search maximise the sum, over a
/// sequence of resolutions from coarse to fine. See docs/ndt_registration.md.
///
/// Pose parameters: x = (tx, ty, tz, phi_x, phi_y, phi_z), metres and
/// radians, T(x) p = Rx(phi_x) Ry(phi_y) Rz(phi_z) p + t, applied on the left
/// of the current estimate (pose = T(x) * estimate), so every Newton step
/// starts from x = 0 and the Euler angles stay far from gimbal lock.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace icrkit::ndt {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Which target cells a transformed source point is scored against.
enum class NdtNeighbourhood {
  Single,  ///< the cell containing the point (Magnusson's basic form)
  Face7,   ///< that cell and its six face neighbours (smoother score, wider basin)
  All27,   ///< the 3x3x3 block around it
};

struct NdtParameters {
  /// Cell edge lengths in metres, coarse to fine; each resolution starts from
  /// the previous one's result. The defaults suit objects of ~10-30 cm
  /// scanned at ~1 mm spacing (the Stanford bunny).
  std::vector<double> resolutions{0.04, 0.02, 0.01};
  /// Cells with fewer target points are left out (their covariance is noise).
  /// This and `min_eigenvalue_ratio` are read when the NdtTarget is built;
  /// registration uses the target's values.
  int min_points_per_cell = 5;
  /// Eigenvalues of a cell covariance are raised to at least this fraction of
  /// the largest, so a planar cell has a finite inverse (Magnusson 6.2; PCL
  /// uses the same 0.01).
  double min_eigenvalue_ratio = 0.01;
  /// Expected fraction of source points with no counterpart in the target.
  double outlier_ratio = 0.55;
  /// true: d1, d2 come from the mixture written in units of the cell edge
  /// (c2 = outlier_ratio), independent of the resolution in metres. false:
  /// Magnusson's constants with the cell volume in cubic metres, which at
  /// centimetre resolutions make d1 ~ -1e-5 (see docs/ndt_registration.md).
  bool scale_invariant_constants = true;
  NdtNeighbourhood neighbourhood = NdtNeighbourhood::Face7;
  /// When > 0, the source is replaced by the centroids of its points in cubes
  /// of this edge (metres) before registering: fewer points, faster, at some
  /// cost in accuracy. 0 (default): every source point.
  double source_voxel_size = 0.0;
  /// Newton iterations per resolution (line-search evaluations not counted).
  int max_iterations = 40;
  /// Converged when a step moves the pose less than both (metres, radians).
  /// 10 um and 1e-5 rad: a hundredth of the accuracy the registration
  /// reaches on real scans (0.1 mm, 0.1 degree); tighter values cost 1.7x
  /// the time for changes below 1 um (bench/ndt_vs_pcl.cpp).
  double translation_epsilon = 1e-5;
  double rotation_epsilon = 1e-5;
  /// The line search never moves further than this in one step: a fraction
  /// of the cell edge (translation) and radians (rotation). Keeps a Newton step
  /// taken on a poor local quadratic inside the basin.
  double max_step_cells = 0.5;
  double max_step_rotation = 0.1;
  /// Evaluations of score + gradient per line search (More-Thuente).
  int max_line_search_evaluations = 10;
};

/// The Gaussians of one resolution (private layout).
class NdtVoxelGrid;

/// The target side, built once and reusable for any number of registrations
/// (read-only afterwards, so concurrent registrations may share it).
class NdtTarget {
public:
  /// Keeps a copy of the positions and builds a grid for every resolution in
  /// `params.resolutions`; a registration at another resolution builds that
  /// grid for itself. Throws InputError for an empty cloud, a non-finite
  /// coordinate, a resolution <= 0 or a grid without any usable cell.
  explicit NdtTarget(const PointCloud& cloud, const NdtParameters& params = {});
  ~NdtTarget();
  NdtTarget(NdtTarget&&) noexcept;
  NdtTarget& operator=(NdtTarget&&) noexcept;

  std::size_t size() const { return points_.size(); }
  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  /// Number of Gaussians at a prebuilt resolution (0 when not prebuilt).
  std::size_t cellCount(double resolution) const;
  /// The prebuilt grid of this resolution, or nullptr.
  const NdtVoxelGrid* grid(double resolution) const;
  int minPointsPerCell() const { return min_points_; }
  double minEigenvalueRatio() const { return min_eigenvalue_ratio_; }

private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::unique_ptr<NdtVoxelGrid>> grids_;
  int min_points_ = 5;
  double min_eigenvalue_ratio_ = 0.01;
};

struct NdtResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< maps source points into the target frame
  /// Final score at the finest resolution: sum over the source points of
  /// -d1 exp(-d2/2 m), m the Mahalanobis distance (higher is better).
  double score = 0.0;
  /// Score divided by the number of source points times -d1: 0 when no point
  /// is near a Gaussian, about 1 when every point sits on the mean of its own
  /// cell (a little more with Face7 / All27, where neighbouring cells add).
  double normalized_score = 0.0;
  std::vector<int> iterations;  ///< Newton iterations per resolution
  bool converged = false;       ///< the finest resolution stopped on the step size
  /// Hessian of the (negated) score w.r.t. x at the result, finest
  /// resolution: positive semi-definite at a maximum; a candidate information
  /// matrix for a pose-graph edge (up to scale).
  Matrix6d hessian = Matrix6d::Zero();
  std::size_t points_scored = 0;  ///< source points that met a Gaussian at the end
  double time_ms = 0.0;
};

/// Registers `source` onto `target` starting from `initial_guess`
/// (source -> target). Throws InputError for an empty or non-finite source,
/// bad parameters, or when no source point meets a Gaussian at the start.
NdtResult registerNdt(const PointCloud& source, const NdtTarget& target, const Eigen::Isometry3d& initial_guess,
                      const NdtParameters& params = {});

/// The objective at one resolution: f(x) = -score(T(x) * pose), its gradient
/// and Hessian w.r.t. x (Magnusson Eq. 6.12-6.13 with the rotation
/// derivatives of 6.17-6.21). Exposed for tests and diagnostics.
struct NdtEvaluation {
  double value = 0.0;  ///< -score (minimised)
  Vector6d gradient = Vector6d::Zero();
  Matrix6d hessian = Matrix6d::Zero();
  std::size_t points_scored = 0;
};
NdtEvaluation evaluateNdt(const PointCloud& source, const NdtTarget& target, double resolution,
                          const Eigen::Isometry3d& pose, const Vector6d& x, const NdtParameters& params = {});

/// The mixture constants (d1 < 0, d2 > 0) for a resolution in metres.
struct NdtConstants {
  double d1 = 0.0, d2 = 0.0;
};
NdtConstants ndtConstants(double resolution, const NdtParameters& params);

/// T(x) as an isometry.
Eigen::Isometry3d ndtPoseFromParameters(const Vector6d& x);

}  // namespace icrkit::ndt
