#pragma once
/// \file
/// Per-scan filters on the range image. Each one sets the range of the
/// pixels it rejects to 0, drops their points and reports how many it
/// removed, so that a pipeline log shows where the points went.

#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>

namespace icrkit::reconstruction {

/// What a filter did to one scan.
struct FilterReport {
  std::size_t pixels_before = 0;  ///< valid pixels when the filter started
  std::size_t removed = 0;        ///< pixels it invalidated (their points are dropped)
};

struct ConfidenceFilterParameters {
  /// Pixels whose confidence is below this (0..255) are removed; 0 = off.
  /// Needs a confidence image; a scan without one is left alone.
  int min_confidence = 0;
  /// Pixels whose amplitude (a ToF camera's CH_IR intensity image, 0..255)
  /// is below this are removed: weak returns are the noisiest. 0 = off;
  /// colour images are never used.
  int min_amplitude = 0;
};
FilterReport filterConfidence(RangeScan& scan, const ConfidenceFilterParameters& params);

struct JumpEdgeParameters {
  /// A pixel is a jump edge (flying pixel, mixed pixel) when, for one of its
  /// 8 neighbours, the segment between the two points makes less than this
  /// angle with the pixel's line of sight (radians). Mixed pixels lie on
  /// the line between foreground and background, i.e. along the rays; a
  /// real surface seen that obliquely is not measured reliably either.
  /// Default 10 degrees (Fuchs and May use values of 5-15 degrees).
  double min_angle = 10.0 * 3.14159265358979323846 / 180.0;
  /// Neighbours whose ranges differ by less than this (metres) never make
  /// an edge: sensor noise on a grazing surface is not a jump.
  double min_jump = 0.005;
};
/// Angle-based jump-edge removal (Fuchs and May 2008; May et al. 2009):
/// evaluated on the unfiltered image, then applied at once.
FilterReport filterJumpEdges(RangeScan& scan, const JumpEdgeParameters& params);

struct RangeGateParameters {
  /// Distance from the sensor along the pixel's ray (metres), whatever
  /// `range_is_depth` says. max <= 0: no upper limit.
  double min_range = 0.0;
  double max_range = 0.0;
};
FilterReport filterRange(RangeScan& scan, const RangeGateParameters& params);

/// Removes the points outside an axis-aligned box in the object frame.
FilterReport filterCropBox(RangeScan& scan, const Eigen::AlignedBox3d& box);

struct PlaneRemovalParameters {
  /// Candidate points: object-frame z within this band (metres) above the
  /// crop box's bottom, where the table or support plate lies. The plane is
  /// fitted to these only, then applied to every point.
  double band = 0.03;
  /// Points closer than this to the plane (metres) are on it.
  double inlier_distance = 0.004;
  /// Also remove points below the plane (the side away from +z): table
  /// edges, the plate's rim and the post under it.
  bool remove_below = true;
  /// RANSAC iterations and seed; the seed fixes the result.
  int iterations = 300;
  std::uint64_t seed = 1;
  /// Fewer inliers than this: no plane is removed (the object alone in view).
  std::size_t min_inliers = 200;
  /// The plane's normal must be within this angle of +z (radians).
  double max_tilt = 0.35;
};
struct PlaneRemovalReport : FilterReport {
  bool found = false;
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();  ///< n.x + d = 0, unit n with n.z > 0 (object frame)
  std::size_t inliers = 0;                          ///< in the band, after refinement
};
/// RANSAC plane fit near the bottom of `box` (object frame), least-squares
/// refinement on the inliers, removal of the plane (and what lies below).
PlaneRemovalReport removeSupportPlane(RangeScan& scan, const Eigen::AlignedBox3d& box,
                                      const PlaneRemovalParameters& params);

}  // namespace icrkit::reconstruction
