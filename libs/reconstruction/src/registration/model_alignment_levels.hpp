#pragma once

#include <Eigen/Geometry>

#include <vector>

namespace icrkit::reconstruction {

/// The largest standard deviation (metres) of `points`: the square root of
/// the largest eigenvalue of their covariance, their spread along their
/// longest principal axis. 0 for fewer than two points.
double largestSpread(const std::vector<Eigen::Vector3d>& points);

/// The object's size as the views see it, unaffected by their poses: the
/// median over the views (those with two points or more) of each one's
/// largestSpread, in its own frame. 0 when no view has two points. The
/// views are pointed to, not copied (the registration's own point sets).
double medianViewSpread(const std::vector<const std::vector<Eigen::Vector3d>*>& views);

/// The levels of `resolutions` (coarse to fine, metres) whose cell edge is
/// at most `max_cell_to_spread` times `spread`, in order; the finest level
/// is always kept. `max_cell_to_spread` <= 0 or `spread` <= 0: all of them.
std::vector<double> modelAlignmentLevels(const std::vector<double>& resolutions, double max_cell_to_spread,
                                         double spread);

}  // namespace icrkit::reconstruction
