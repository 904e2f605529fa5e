#pragma once
/// \file
/// Ball pivoting surface reconstruction (Bernardini et al., "The Ball-Pivoting
/// Algorithm for Surface Reconstruction", IEEE TVCG 1999) from oriented points.
///
/// A ball of radius rho touching three points without containing any other
/// point makes a triangle; the ball then pivots around each edge of the
/// advancing front until it touches the next point. Several increasing radii
/// close the gaps that a small ball falls through, as in the original paper.

#include <icrkit/core/length.hpp>
#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

struct BallPivotingParameters {
  /// Ball radii: metres, or multiples of the median nearest-neighbour
  /// spacing of the points. Resolved, sorted ascending and made unique
  /// before use; each finite and > 0. The default, 1.5 and 2.5 spacings,
  /// follows the detail of an evenly sampled surface (a scanner's grid, a
  /// mesh's vertices) and closes its gaps without capping real holes (see
  /// docs/meshing.md).
  std::vector<Length> radii = {Length::spacings(1.5), Length::spacings(2.5)};
  /// When every radius is relative, one more radius of this factor x the
  /// 90th percentile of the nearest-neighbour distances is added when it
  /// exceeds 3 median spacings: unevenly sampled clouds (random samples,
  /// scans with sparse parts) have gaps several spacings wide. 0 = never.
  double gap_radius_factor = 2.2;
  /// Points closer than this to an earlier point (metres, >= 0) are
  /// duplicates: only the first one of each group can become a vertex, the
  /// others are reported as unused. Unset: 1e-9 times the bounding-box
  /// diagonal.
  std::optional<double> duplicate_distance;
  /// At most this many nearest neighbours of a candidate seed point are
  /// paired when a seed triangle is searched (bounds the quadratic cost at
  /// points that can never seed, such as isolated outliers).
  /// 8: on a fused cloud's noise layer, where tens of thousands of buried
  /// points never seed, 24 cost 1.8x the time for the same mesh.
  std::size_t seed_neighbours = 8;
  /// A cloud fused from many views is a noise layer as thick as its points
  /// are dense, too rough for a ball of a few spacings: the layer's
  /// thickness t (the median RMS distance of the points within 6 spacings
  /// from a quadric fitted to them) is measured and, when this factor x t
  /// exceeds 1.5 spacings, one point per cube of that edge (the one
  /// nearest the cube's centroid) takes part, the others stay unused
  /// vertices; automatic radii then follow the kept points' spacing. A
  /// clean sample (a mesh's vertices, a laser scan) is left alone. 0 = off.
  double thinning_factor = 8.0;
  /// After the pivoting (and hole filling) over the kept points, the points
  /// the thinning left out are put back as vertices: each goes into the
  /// face it projects onto (within half a thinning cell of its plane, the
  /// normals agreeing, at least 0.35 median spacings from the face's
  /// corners and from the points already put into it), and that face is
  /// split around it (a Delaunay
  /// triangulation in its plane, its sides split alike on both faces). The
  /// mesh keeps the thinned mesh's topology (loops, components, no
  /// non-manifold edge) and regains the cloud's density, so regions and
  /// Algorithm 2, which work on vertices, see all of them.
  bool reinsert_thinned = true;
  /// After the last radius, holes whose boundary (a simple cycle of
  /// boundary edges) has at most this many edges and a perimeter of at
  /// most `hole_perimeter_factor` x the largest radius are filled with
  /// faces over their own points (a minimum-weight triangulation whose
  /// faces agree with the point normals; no chord may be an edge already,
  /// so the mesh stays edge-manifold). Such holes remain where a point off
  /// the surface (a stray sample, the noise layer of a fused cloud) is the
  /// first one the ball touches. 0 = none.
  std::size_t close_holes_up_to = 48;
  double hole_perimeter_factor = 8.0;
  /// Larger holes, of up to this many edges, are filled the same way only
  /// where the surface was seen: every point of the fill must lie within
  /// the largest radius of an input point (used or not). An opening no
  /// view saw (an object's base) has none inside and stays open. 0 = none.
  std::size_t seen_holes_up_to = 200;
  /// A hole whose rim is folded over (the surface overlaps itself at the
  /// rim: where two sheets of a noisy layer met, along a sharp edge) has no
  /// fill whose faces all agree with the point normals. With this on, the
  /// holes of either size above that every strict fill left open are, last,
  /// filled with disagreeing faces allowed but penalised, when the whole
  /// fill lies on seen surface (the test of `seen_holes_up_to`), repeats no
  /// face back to back and covers at most `folded_hole_max_share` of the
  /// piece of surface (faces connected across edges) it joins. The fold
  /// stays a crease one or two faces wide; regions and mappings use the
  /// vertex normals, not the faces'.
  bool fill_folded_holes = true;
  /// The outer rim of a flake or of a small open sheet also winds against
  /// its normals, and a fill over it is as large as the sheet: a hole's fill
  /// is a small part of the surface around it.
  double folded_hole_max_share = 0.1;
  /// Finally, components (faces connected through shared points) with
  /// fewer faces than this are taken out, their points left unused: flakes
  /// of a noisy layer beside the surface. 0 = keep everything (the
  /// default: a general mesher does not judge what is noise;
  /// `icrkit reconstruct` sets it for fused clouds).
  std::size_t min_component_faces = 0;

  /// Throws InputError naming the field ("BallPivotingParameters::radii",
  /// "BallPivotingParameters::thinning_factor", ...) for a radius, factor or
  /// distance that is not finite or out of range. ballPivoting() calls it
  /// first; callers may call it before reading a large cloud.
  void validate() const;
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
  double layer_thickness = 0.0;       ///< metres (see `thinning_factor`; 0 when off)
  double thinning_cell = 0.0;         ///< metres; 0 when the cloud was not thinned
  std::size_t thinned_points = 0;     ///< left out of the pivoting by the thinning
  std::size_t reinserted_points = 0;  ///< of those: put back into the faces afterwards (used)
  double mesh_spacing = 0.0;          ///< metres, median spacing of the points that took part
  std::size_t points = 0;
  std::size_t triangles = 0;
  std::size_t used_points = 0;        ///< points referenced by at least one triangle
  std::size_t unused_points = 0;      ///< points no triangle references (kept as vertices)
  std::size_t duplicate_points = 0;   ///< of the unused ones: duplicates of an earlier point
  std::size_t unoriented_points = 0;  ///< of the unused ones: points whose normal is zero
  std::size_t closed_holes = 0;        ///< holes filled after the last radius
  /// Of those: folded holes (`fill_folded_holes`), whose fills have faces
  /// against their points' normals.
  std::size_t folded_holes = 0;
  std::size_t removed_faces = 0;       ///< faces of components below `min_component_faces`
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
