#pragma once
/// \file
/// The last stage of Section II-A and III-B as one call on any cloud with
/// normals (a fused recording, a noisy sample of a CAD surface): the raw
/// mesh (ball pivoting of the cloud as it is) and the filtered mesh (3D-NDT
/// smoothing and preselection, then ball pivoting). `icrkit reconstruct`
/// and the sensitivity study (`icrkit sensitivity`) both mesh this way.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace icrkit::reconstruction {

struct RawAndFilteredParameters {
  /// Smoothing and preselection (with its rule); a radius relative to the
  /// spacing is taken of `reference_spacing` (metres) when that is set and
  /// > 0, else of the cloud's own median spacing.
  ndt::SmoothingParameters smoothing;
  std::optional<double> reference_spacing;
  /// Ball pivoting of both clouds.
  BallPivotingParameters meshing;
  /// false: the raw mesh keeps its noise layer unthinned and its folded
  /// holes open (the paper's baseline: every point as it is, plain ball
  /// pivoting); true: it is meshed like the smoothed cloud.
  bool thin_raw_cloud = false;
  /// The other reading of the paper: excluded points are removed before
  /// ball pivoting, so the filtered mesh has no excluded vertex (and holes
  /// where they were). false (default): they stay vertices, flagged.
  bool mesh_kept_points_only = false;
  /// false: no raw mesh (the paper's baseline; a robot grasps the filtered
  /// one): `raw` stays empty and the filtered mesh comes a third sooner.
  bool make_raw = true;
};

struct RawAndFilteredTimes {
  double raw_mesh_ms = 0.0;
  double smoothing_ms = 0.0;
  double filtered_mesh_ms = 0.0;
};

struct RawAndFilteredMeshes {
  TriangleMesh raw;
  BallPivotingReport raw_meshing;
  /// Smoothed positions, v3 normals, the attributes `cardinality`,
  /// `flatness`, `displacement` and `excluded` (unless the rule is none).
  TriangleMesh filtered;
  ndt::SmoothingReport smoothing;
  BallPivotingReport filtered_meshing;
  std::size_t dropped_excluded = 0;  ///< with mesh_kept_points_only
  RawAndFilteredTimes times;
};

/// `cloud` must have normals (the raw mesh pivots on them). With
/// `viewpoints` (one per point) the smoothed normals face each point's own
/// sensor, else they keep the smoothing's orientation. Progress stages:
/// "raw mesh", "smoothing", "filtered mesh". Throws InputError for a cloud
/// without normals or bad parameters.
RawAndFilteredMeshes meshRawAndFiltered(const PointCloud& cloud, const RawAndFilteredParameters& params,
                                        const std::vector<Eigen::Vector3d>& viewpoints = {},
                                        const ProgressCallback& progress = {});

}  // namespace icrkit::reconstruction
