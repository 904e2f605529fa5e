#pragma once
/// \file
/// The 3D-NDT smoothing layer (Algorithm 1 of Krug et al.) and point
/// preselection (Section III-B.2).
///
/// Per point p_s: the spherical window W_s of radius r (points within r,
/// p_s included), its mean mu_s and covariance Sigma_s, eigenvalues
/// l1 >= l2 >= l3 with vectors v1..v3, and the projection onto the plane of
/// the two dominant vectors: p_s' = p_s + v3 (mu_s - p_s)^T v3. Windows are
/// taken from the input positions of the pass (Jacobi style), so the result
/// does not depend on point order or thread count.
///
/// Preselection (preselection.hpp): from the cardinality |W_s| and the
/// flatness F = sqrt(l2 / l3) of the first pass's windows, by the rule of
/// `SmoothingParameters::preselection` (default: the robust rule).

#include <icrkit/core/length.hpp>
#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/ndt/preselection.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cmath>
#include <optional>
#include <vector>

namespace icrkit::ndt {

struct SmoothingParameters {
  /// Window radius r: metres, or a multiple of the median nearest-neighbour
  /// spacing of the input (default 4 spacings). Finite and > 0.
  Length radius = Length::spacings(4.0);
  /// k passes; each recomputes the windows from the previous pass's output.
  /// Preselection uses the statistics of the first pass (the measured data).
  int passes = 1;
  /// Rule none: no `excluded` attribute is written.
  PreselectionParameters preselection;
  /// Normals (v3) point towards this sensor position when given, else
  /// towards each point's own sensor when `viewpoints` (one per point) are
  /// given, else outwards from the centroid, made consistent over the
  /// neighbour graph.
  std::optional<Eigen::Vector3d> viewpoint;
  /// Per point: the sensor that saw it (a fused cloud's viewpoint_x/y/z).
  /// The graph orientation cannot know which side of a thin wall or of a
  /// sharp crease faces out; the sensor that saw the point can.
  std::vector<Eigen::Vector3d> viewpoints;
  /// l3 is floored at this fraction of l2, capping the flatness at
  /// 1 / sqrt(floor) = 100. Real sensor noise stays far from the cap (a 4 mm
  /// window would need a noise thickness below 0.02 mm); exactly coplanar
  /// windows (three points, quantised depth) would otherwise get flatness
  /// ~1e6 and drag the mean threshold above every other point.
  double flatness_floor = 1e-4;
  /// One-sided windows: when the cloud comes with normals, a window keeps
  /// only the points whose input normal is within this angle (radians) of
  /// the query point's, so a wall thinner than the window (a cup's, 2-3 mm
  /// against a 6 mm window) is not pulled together with its other side,
  /// whose normals face the other way. A point without a normal (zero)
  /// keeps and is kept by every window. >= pi (default): every point of the
  /// radius, the paper's window.
  double max_normal_angle = M_PI;

  /// Throws InputError naming the field ("SmoothingParameters::passes",
  /// "PreselectionParameters::flatness_threshold", ...) for a value out of
  /// range. smoothPointCloud() calls it first; callers may call it before
  /// reading a large cloud.
  void validate() const;
};

struct SmoothingReport {
  std::size_t points = 0;
  double radius_m = 0.0;
  double median_spacing_m = 0.0;  ///< 0 when the radius was given in metres (not measured)
  int passes = 0;
  std::size_t small_windows = 0;  ///< windows with fewer than 3 points: left unchanged
  /// Statistics of the first pass's windows and what the rule made of them
  /// (means and medians also with rule none).
  PreselectionReport preselection;
  double mean_displacement_m = 0.0;
  double max_displacement_m = 0.0;
  double time_ms = 0.0;
};

/// Smooths `cloud` in place and adds the per-point attributes `cardinality`
/// (int), `flatness` (float), `displacement` (float, metres, total over the
/// passes), `normal_sigma` (float, radians) and `position_sigma` (float,
/// metres) of the first pass's fit (fit_uncertainty.hpp; later passes refit
/// points that are no longer measurements, so their residuals would claim a
/// certainty the data never had), `excluded` (uchar, unless the rule is
/// none) and replaces the normals
/// by the v3 estimates of the last pass (a point whose window holds fewer
/// than 3 points keeps its input normal, or gets none when the cloud had none). Throws InputError for an empty
/// cloud, a non-finite coordinate (naming the point), r <= 0 or passes < 1.
SmoothingReport smoothPointCloud(PointCloud& cloud, const SmoothingParameters& params = {},
                                 const ProgressCallback& progress = {});

/// Flatness sqrt(l2 / max(l3, floor * l2)); 0 when l2 = 0 (the window is a
/// point or a line: not a surface).
double flatness(const Eigen::Vector3d& eigenvalues, double floor = 1e-4);

}  // namespace icrkit::ndt
