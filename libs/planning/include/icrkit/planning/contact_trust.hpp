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
///   and vertices preselection `excluded`.
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
  /// ... to within this angle (radians).
  double max_normal_spread_rad = 0.35;
  /// When set and the mesh has `normal_sigma` (radians), vertices above it
  /// are not trusted.
  std::optional<double> max_normal_sigma_rad = 0.25;

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
