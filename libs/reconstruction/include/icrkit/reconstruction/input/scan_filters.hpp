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

struct ForegroundEdgeParameters {
  /// Pixels taken off a surface's edge where it stands in front of the
  /// background or of nothing (no return): a structured-light camera
  /// spreads a foreground edge over the background by a pixel or two, a
  /// ToF camera mixes it, and what the jump-edge test leaves of that lies
  /// off the surface, worst on thin parts that are mostly edge (a bunny's
  /// ears). 0 = off.
  int pixels = 0;
  /// A neighbour whose range exceeds the pixel's by more than this
  /// (metres) is background; so is a pixel without a range in a gap of at
  /// least `min_gap_pixels` (4-connected): the space around the object,
  /// not a dropout inside a surface, which does not spread an edge.
  double min_jump = 0.01;
  std::size_t min_gap_pixels = 25;
};
/// Erodes every foreground edge of the range image by `pixels` (Chebyshev
/// distance): evaluated on the unfiltered image, then applied at once.
/// Pixels at the image border are not edges by the border alone.
FilterReport filterForegroundEdges(RangeScan& scan, const ForegroundEdgeParameters& params);

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
  /// The object frame's up direction (unit): the object stands on the
  /// plane's side it points to (input/up_axis.hpp estimates it).
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  /// Candidate points: height along `up` within this band (metres) above
  /// the crop box's lowest corner, where the table or support plate lies.
  /// The plane is fitted to these only, then applied to every point.
  double band = 0.03;
  /// Points closer than this to the plane (metres) are on it.
  double inlier_distance = 0.004;
  /// Also remove points below the plane (the side away from `up`): table
  /// edges, the plate's rim and the post under it.
  bool remove_below = true;
  /// RANSAC iterations and seed; the seed fixes the result.
  int iterations = 300;
  std::uint64_t seed = 1;
  /// Fewer inliers than this: no plane is removed (the object alone in view).
  std::size_t min_inliers = 200;
  /// The plane's normal must be within this angle of `up` (radians).
  double max_tilt = 0.35;
  /// A support faces up: the plane RANSAC found is kept only when the
  /// candidates near it whose own normal (of their `normal_neighbours`
  /// nearest candidates, turned towards the sensor) is within
  /// `max_normal_angle` of `up` and of the plane number `min_inliers` (at
  /// most `normal_samples` of them tested, an even stride, the count
  /// scaled). Without this the lowest slab of an object that stands on
  /// nothing in view (the real recording's bunny) fits a horizontal plane
  /// 4 mm thick, and the object loses its bottom centimetre.
  double max_normal_angle = 0.7853981633974483;
  std::size_t normal_neighbours = 24;
  std::size_t normal_samples = 4000;
  /// ... and they must be at least this share of the samples near the
  /// plane: a few up-facing patches in an object's lowest slab (the tops of
  /// a bunny's feet) do not make its sides a table.
  double min_facing_share = 0.5;
};
struct PlaneRemovalReport : FilterReport {
  bool found = false;
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();  ///< n.x + d = 0, unit n with n.up > 0 (object frame)
  std::size_t inliers = 0;                          ///< in the band, after refinement
};
/// RANSAC plane fit near the bottom of `box` along `up` (object frame), least-squares
/// refinement on the inliers, removal of the plane (and what lies below).
/// With no table in view, an object's own top facing up inside the band
/// is taken for one (docs/reconstruction.md, "Known limits").
PlaneRemovalReport removeSupportPlane(RangeScan& scan, const Eigen::AlignedBox3d& box,
                                      const PlaneRemovalParameters& params);

}  // namespace icrkit::reconstruction
