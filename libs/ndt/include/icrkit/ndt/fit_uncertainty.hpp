#pragma once
/// \file
/// How uncertain a point's normal and position are after a local plane fit
/// (the smoothing layer's window, or the raw normal estimation's).
///
/// Model (docs/smoothing.md, "Uncertainty per point"): the window's k points scatter about a plane
/// with independent Gaussian noise of standard deviation s along its normal;
/// their in-plane spread is the covariance's two dominant eigenvalues
/// l1 >= l2 (population covariance, divided by k). Then, to first order,
/// - s^2 = l3 k / (k - 3): the residual variance, with the three degrees of
///   freedom the plane used (offset, two tilts) given back; curvature inside
///   the window adds to l3, so a curved window reads as noisier (never less
///   certain than it is);
/// - each tilt of the fitted normal about v1, v2 has variance s^2 / (k l_i),
///   the slope variance of a least-squares fit; `normal_sigma` is the root
///   mean square angle between fitted and true normal,
///   sqrt(s^2 / k (1 / l1 + 1 / l2));
/// - a point projected onto the fitted plane (smoothing) is off the true
///   plane by the fit's offset error plus its tilts times the point's
///   in-plane distance a from the window mean:
///   position_sigma^2 = s^2 / k (1 + a1^2 / l1 + a2^2 / l2);
///   a point left where it was measured (raw) keeps its own noise:
///   position_sigma = s.
/// A window of fewer than 4 points, or a degenerate one (l2 = 0), carries no
/// residual: the normal could be anything in its half-space (pi / 2) and the
/// position is known to the window radius.

#include <Eigen/Core>

#include <cstddef>

namespace icrkit::ndt {

struct FitUncertainty {
  double normal_sigma = 0.0;    ///< radians, RMS angle of the normal error
  double position_sigma = 0.0;  ///< metres, standard deviation along the normal
};

enum class FittedPoint {
  Projected,  ///< moved onto the fitted plane (the smoothing layer)
  Measured    ///< left where it was measured (raw normal estimation)
};

/// `eigenvalues` l1 >= l2 >= l3 of the window's population covariance,
/// `count` its points, `offset` the point minus the window mean, `axes` the
/// eigenvectors (columns v1, v2, v3), `radius` the window radius (the
/// fallback position uncertainty).
FitUncertainty planeFitUncertainty(const Eigen::Vector3d& eigenvalues, const Eigen::Matrix3d& axes, std::size_t count,
                                   const Eigen::Vector3d& offset, double radius, FittedPoint point);

/// Attribute names (float, one per point) as they travel to meshes.
inline constexpr const char* kNormalSigmaAttribute = "normal_sigma";
inline constexpr const char* kPositionSigmaAttribute = "position_sigma";

}  // namespace icrkit::ndt
