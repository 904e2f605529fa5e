#pragma once
/// \file
/// Ball pivoting surface reconstruction (Bernardini et al., "The Ball-Pivoting
/// Algorithm for Surface Reconstruction", IEEE TVCG 1999) from oriented points.
///
/// A ball of radius rho touching three points without containing any other
/// point makes a triangle; the ball then pivots around each edge of the
/// advancing front until it touches the next point. Several increasing radii
/// close the gaps that a small ball falls through, as in the original paper.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

struct BallPivotingParameters {
  /// Ball radii in metres. Empty: `radius_factors` times the median
  /// nearest-neighbour spacing of the points. Sorted ascending and made
  /// unique before use; each must be finite and > 0.
  std::vector<double> radii;
  /// Used when `radii` is empty: radii = factor x the median
  /// nearest-neighbour spacing. The defaults follow the detail of an evenly
  /// sampled surface (a scanner's grid, a mesh's vertices) and close its
  /// gaps without capping real holes (see docs/meshing.md).
  std::vector<double> radius_factors = {1.5, 2.5};
  /// With automatic radii, one more radius of this factor x the 90th
  /// percentile of the nearest-neighbour distances is added when it exceeds
  /// 3 median spacings: unevenly sampled clouds (random samples, scans with
  /// sparse parts) have gaps several spacings wide. 0 = never.
  double gap_radius_factor = 2.2;
  /// Points closer than this to an earlier point (metres) are duplicates:
  /// only the first one of each group can become a vertex, the others are
  /// reported as unused. Negative: 1e-9 times the bounding-box diagonal.
  double duplicate_distance = -1.0;
  /// At most this many nearest neighbours of a candidate seed point are
  /// paired when a seed triangle is searched (bounds the quadratic cost at
  /// points that can never seed, such as isolated outliers).
  std::size_t seed_neighbours = 24;
  /// After the last radius, boundary loops of up to this many edges (3 or
  /// 4; 0 = none) are closed with one or two faces when their winding
  /// agrees with the point normals. Such gaps remain where a point off the
  /// surface (a stray or noisy sample) is the first one the ball touches.
  std::size_t close_holes_up_to = 4;
};

/// Per-radius statistics, in the order the radii were used.
struct BallPivotingPass {
  double radius = 0.0;             ///< metres
  std::size_t seeds = 0;           ///< seed triangles found with this radius
  std::size_t triangles = 0;       ///< triangles added with this radius (seeds included)
  double time_ms = 0.0;            ///< wall-clock time of this radius
};

struct BallPivotingReport {
  std::vector<BallPivotingPass> passes;
  double median_spacing = 0.0;        ///< metres, of the input points
  std::size_t points = 0;
  std::size_t triangles = 0;
  std::size_t used_points = 0;        ///< points referenced by at least one triangle
  std::size_t unused_points = 0;      ///< points no triangle references (kept as vertices)
  std::size_t duplicate_points = 0;   ///< of the unused ones: duplicates of an earlier point
  std::size_t unoriented_points = 0;  ///< of the unused ones: points whose normal is zero
  std::size_t closed_holes = 0;        ///< small loops closed after the last radius
  std::size_t boundary_edges = 0;
  std::size_t boundary_loops = 0;
  std::size_t non_manifold_edges = 0;  ///< always 0 by construction; reported as a check
  std::size_t components = 0;          ///< connected parts of the triangles
  long euler_characteristic = 0;       ///< V - E + F over the used points
};

struct BallPivotingResult {
  /// Vertices are exactly the input points, in input order, with their
  /// normals, colours and attributes; the faces are wound counter-clockwise
  /// seen from the side the normals point to.
  TriangleMesh mesh;
  BallPivotingReport report;
};

/// Meshes an oriented point cloud. Requires finite coordinates, a finite
/// normal per point (not necessarily unit length) and at least three
/// points with a non-zero one; throws InputError naming "point cloud" and
/// the offending point, or the parameter ("--radii"), otherwise. Points
/// whose normal is zero (e.g. where a plane fit had too few neighbours)
/// take no part and are reported as unoriented.
/// Single-threaded and deterministic: the same input gives the same mesh.
BallPivotingResult ballPivoting(const PointCloud& cloud, const BallPivotingParameters& params = {});

/// The radii `ballPivoting` would use for this cloud (sorted, unique, metres).
std::vector<double> ballPivotingRadii(const PointCloud& cloud, const BallPivotingParameters& params);

}  // namespace icrkit::reconstruction
