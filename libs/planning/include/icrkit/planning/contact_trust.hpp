#pragma once
/// \file
/// Where a finger may be put on a reconstructed mesh: vertices whose
/// position and normal a robot can trust. A region grown over a vertex
/// promises the task for the contact the mesh shows there; on the true
/// object the finger touches the surface that faces it, whose normal is the
/// mesh's only where the mesh is right. It is wrong, measurably, in three
/// places (docs/planning.md):
/// - near the rim of the seen surface (the mesh's boundary): normals there
///   are fitted from one side, and the true surface may turn away;
/// - where the normals under a fingertip disagree (creases, edges, thin
///   features, noise): a finger there touches one of several surfaces;
/// - where the reconstruction says so itself: `normal_sigma` above a bound,
///   vertices preselection `excluded`, and surface supported by few points
///   (`cardinality`, the points of a vertex's NDT window, far below the
///   mesh's median: seen in few views, at grazing angles, or a ghost of a
///   misregistered view) under the fingertip.
/// Untrusted vertices are never a contact and never join a region.

#include <icrkit/core/triangle_mesh.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace icrkit::planning {

struct ContactTrustParameters {
  /// Vertices closer than this (metres, along mesh edges) to the mesh's
  /// boundary are not trusted (0: only the boundary vertices themselves).
  double rim_distance_m = 0.004;
  /// The fingertip's footprint (metres): the normals of every vertex within
  /// this distance must agree with the vertex's own ...
  double footprint_radius_m = 0.003;
  /// ... to within this angle (radians) of the footprint's mean normal,
  /// the vertex's own normal always and ...
  double max_normal_spread_rad = 0.35;
  /// ... all but this fraction of the others (0: every one). A crease or a
  /// thin feature puts a large share of the footprint on another surface;
  /// a few noisy normals of ball pivoting's small triangles do not.
  double max_spread_fraction = 0.1;
  /// When set and the mesh has `normal_sigma` (radians), vertices above it
  /// are not trusted.
  std::optional<double> max_normal_sigma_rad = 0.25;
  /// When set and the mesh has `cardinality`, a vertex is not trusted when
  /// some surface vertex under its footprint has a cardinality below this
  /// fraction of the mesh's median cardinality (dimensionless). Phantom
  /// surfaces of misregistered views are thinly supported: on the nine
  /// simulated datasets with mobile-robot poses, 1/3 flags 63-100 % of the
  /// vertices more than 5 mm from the true surface and 6-23 % of the others
  /// (docs/planning.md).
  std::optional<double> min_relative_support = 1.0 / 3.0;
  /// When set and the mesh has `flatness` (the NDT window's planarity, the
  /// smoothing's attribute), vertices whose flatness is below this fraction
  /// of the mesh's median are not trusted: the smoothing rounded a feature
  /// there (a wheel, a step, an edge) that the true surface has, and a
  /// finger approaching along the rounded normal touches the feature at
  /// another angle. 0.75 flags 55-98 % of the vertices whose by-touch
  /// normal is more than 30 deg off on the toys (7-23 % of the others).
  std::optional<double> min_relative_flatness = 0.75;

  /// InputError naming the field (`ContactTrustParameters::rim_distance_m`, ...)
  /// for a negative or non-finite value.
  void validate() const;
};

struct ContactTrustReport {
  std::size_t vertices = 0;        ///< vertices some face uses
  std::size_t trusted = 0;
  std::size_t excluded = 0;        ///< by the given mask (preselection)
  std::size_t near_rim = 0;        ///< untrusted: within rim_distance_m of the boundary
  std::size_t normal_spread = 0;   ///< untrusted: normals under the footprint disagree
  std::size_t normal_sigma = 0;    ///< untrusted: normal_sigma above the bound
  std::size_t weak_support = 0;    ///< untrusted: thinly supported surface under the footprint
  std::size_t low_flatness = 0;    ///< untrusted: a rounded feature (flatness far below the median)
};

struct ContactTrust {
  /// One flag per vertex, non-zero: no finger there (the mask a
  /// GraspableObject takes). Vertices no face uses are flagged too.
  std::vector<std::uint8_t> untrusted;
  ContactTrustReport report;  ///< a vertex is counted under the first reason that applies, in field order
};

/// `excluded`: empty or one flag per vertex (the preselection). The mesh
/// needs unit normals on the vertices its faces use.
ContactTrust assessContactTrust(const TriangleMesh& mesh, const std::vector<std::uint8_t>& excluded,
                                const ContactTrustParameters& params = {});

}  // namespace icrkit::planning
