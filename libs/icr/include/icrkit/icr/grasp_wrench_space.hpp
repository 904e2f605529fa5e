#pragma once
/// \file
/// The Grasp Wrench Space: the convex hull of a grasp's primitive wrenches,
/// computed with reentrant qhull (one qhT per call, so calls may run in
/// parallel threads; qhull never prints).

#include <icrkit/icr/wrench.hpp>

#include <string>
#include <vector>

namespace icrkit::icr {

struct HullParameters {
  /// qhull options. "Qt Qx" (triangulated output, exact pre-merges) is the
  /// reference library's choice: merged hulls have fewer facets per search
  /// zone, which keeps region growth fast. "Q0" (no pre-merging) builds the
  /// hull in about 60 % of the time and gives the same regions on all
  /// reference grasps, but its extra facets slow the growth of large regions
  /// (docs/performance.md); pair it with fallback_options = "Qt Qx".
  std::string qhull_options = "Qt Qx";
  /// Options of a second attempt when qhull stops with the first ones (it can
  /// give up on nearly degenerate input without merging). Empty: no retry.
  std::string fallback_options;
  /// The origin must be at least this far inside every facet for force closure.
  double force_closure_threshold = 1e-10;
};

struct GraspWrenchSpace {
  bool force_closure = false;
  std::string reason;  ///< why it is not force closure (empty otherwise)
  /// Smallest distance from the origin to a facet hyperplane: the radius of
  /// the largest origin-centred ball inside the hull (negative when the
  /// origin is outside; 0 when there is no full-dimensional hull).
  double epsilon = 0.0;
  /// Outward unit facet normals (one column per facet) and offsets: the hull
  /// is { w : normals.col(f) . w + offsets[f] <= 0 }.
  WrenchSet normals;
  std::vector<double> offsets;
  std::vector<std::vector<int>> facet_vertices;  ///< input wrench indices per facet
  std::vector<int> hull_vertices;                ///< input wrench indices that are hull vertices, ascending
  std::string qhull_options;                     ///< the options of the attempt that built this hull

  std::size_t facetCount() const { return offsets.size(); }
};

/// Builds the hull of the columns of `wrenches`. A degenerate set (fewer than
/// 7 wrenches, lower-dimensional, qhull precision failure) gives a result
/// with force_closure = false and the reason, never an exception.
GraspWrenchSpace computeGraspWrenchSpace(const WrenchSet& wrenches, const HullParameters& params = {});

}  // namespace icrkit::icr
