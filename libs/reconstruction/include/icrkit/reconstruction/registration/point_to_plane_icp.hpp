#pragma once
/// \file
/// Point-to-plane ICP (Chen and Medioni 1992) between two scans, the fine
/// stage of the pair-wise registration: NDT brings a pair within a few
/// millimetres, ICP against the target's tangent planes finishes at the
/// sensor's noise scale, where an NDT cell (5 mm and up on a depth camera)
/// is too coarse a model of a curved surface.
///
/// Correspondences are nearest neighbours within a distance that shrinks
/// stage by stage; residuals along the target normal are weighted by a
/// Tukey biweight, so the parts of a view the other one does not see (the
/// non-overlap, which is most of a pair of views 40 degrees apart) drop out
/// instead of pulling.
///
/// Conventions as registration_observability.hpp: the Hessian is with
/// respect to a left perturbation x = [t; theta] of the pose in the target
/// frame.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <memory>
#include <vector>

namespace icrkit {
class KdTree;
}

namespace icrkit::reconstruction {

struct PointToPlaneIcpParameters {
  /// Correspondence distance per stage (metres), coarse to fine; each
  /// stage starts from the previous one's pose.
  std::vector<double> max_distances{0.006, 0.003, 0.0015};
  /// Gauss-Newton iterations per stage (each with fresh correspondences).
  int max_iterations = 12;
  /// Tukey biweight width (metres along the target normal): residuals
  /// beyond it get no weight. Three to four times a depth camera's noise at
  /// arm's length. It never exceeds the stage's distance.
  double kernel_width = 0.003;
  /// A stage stops when a step moves the pose less than both (metres,
  /// radians): 5 um and 1e-5 rad, a fortieth of a depth camera's precision.
  double translation_epsilon = 5e-6;
  double rotation_epsilon = 1e-5;
  /// Fewer weighted correspondences than this: the registration fails.
  std::size_t min_correspondences = 30;
};

/// The target side: points with unit normals (any sign) and a search tree,
/// built once per scan and shared read-only by any number of registrations.
class IcpTarget {
public:
  /// Throws InputError when the sizes differ or there are no points.
  IcpTarget(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);
  ~IcpTarget();
  IcpTarget(IcpTarget&&) noexcept;
  IcpTarget& operator=(IcpTarget&&) noexcept;

  const std::vector<Eigen::Vector3d>& points() const;
  const std::vector<Eigen::Vector3d>& normals() const;
  /// The nearest point within `max_distance`, or -1.
  long nearest(const Eigen::Vector3d& query, double max_distance) const;
  /// The search tree over points().
  const KdTree& tree() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct PointToPlaneIcpResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< source -> target
  bool converged = false;  ///< the last stage stopped on the step size
  bool failed = false;     ///< too few correspondences at some stage
  int iterations = 0;      ///< over all stages
  /// At the final pose, last stage: weighted correspondences, their
  /// fraction of the source points, and the weighted RMS residual along the
  /// normals (metres).
  std::size_t correspondences = 0;
  double inlier_fraction = 0.0;
  double rms_m = 0.0;
  /// sum w J^T J at the final pose (left perturbation, target frame): the
  /// information of the result up to the residuals' variance.
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
};

/// Registers `source` onto `target` from `initial_guess` (source -> target).
/// Never throws for poor data: a failure is reported in the result.
PointToPlaneIcpResult registerPointToPlane(const std::vector<Eigen::Vector3d>& source, const IcpTarget& target,
                                           const Eigen::Isometry3d& initial_guess,
                                           const PointToPlaneIcpParameters& params = {});

}  // namespace icrkit::reconstruction
