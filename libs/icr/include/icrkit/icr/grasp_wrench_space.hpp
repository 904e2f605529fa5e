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
  /// qhull options of the first attempt. "Q0" (no pre-merging) builds the
  /// hull in about 60 % of the time of qhull's default merging and gives the
  /// same facets and regions on every reference grasp (docs/performance.md).
  /// Without merging qhull may stop on nearly degenerate input or leave a
  /// facet that some wrench lies beyond; either makes the hull be rebuilt
  /// with `fallback_options` (every wrench is checked against every facet).
  /// Nearly coplanar facets are kept unmerged: the hull is right, with more
  /// facets (and zone constraints) than a merged one.
  std::string qhull_options = "Q0";
  /// Options of the second attempt: triangulated output with exact
  /// pre-merges, the reference library's choice. Empty: no retry.
  std::string fallback_options = "Qt Qx";
  /// The origin must be at least this far inside every facet for force closure.
  double force_closure_threshold = 1e-10;
  /// When a fallback is set, a first-attempt hull with a wrench further than
  /// this beyond one of its facets (relative to the largest wrench norm) is
  /// rejected and rebuilt with the fallback options.
  double convexity_tolerance = 1e-9;
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

/// True when no column of `wrenches` lies beyond a facet of `gws` by more
/// than `relative_tolerance` times the largest column norm.
bool hullContains(const GraspWrenchSpace& gws, const WrenchSet& wrenches, double relative_tolerance = 1e-9);

}  // namespace icrkit::icr
