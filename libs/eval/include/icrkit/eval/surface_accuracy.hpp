#pragma once
/// \file
/// How true a reconstructed mesh is to a reference surface (the CAD mesh),
/// per vertex, where fingers go: the distance to the reference and the angle
/// between the vertex normal and the reference face normal where a finger
/// approaching along the vertex normal would touch the reference (else at
/// the nearest reference point), split into vertices near the reference's sharp edges
/// (creases whose faces differ by more than `crease_angle_rad`) and the
/// rest. Smoothing rounds edges over its window and pulls thin walls
/// together; these figures show where (issue 34, docs/evaluation.md).
///
/// The meshes must share one frame (align first: rigid_alignment.hpp).
/// Vertices no face uses are ignored. The reference's face normals follow
/// its winding, turned to agree with its vertex normals when it has them.

#include <icrkit/core/triangle_mesh.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace icrkit::eval {

struct SurfaceAccuracyParameters {
  /// A reference edge is sharp when its two faces' normals differ by more
  /// than this (radians; 30 deg).
  double crease_angle_rad = 30.0 * M_PI / 180.0;
  /// Vertices whose nearest reference point lies within this distance
  /// (metres) of a sharp edge are "near edges".
  double edge_distance_m = 0.004;
  /// A vertex's normal is compared with the reference face that the line
  /// along it first meets turned its way, within this distance (metres), by
  /// touch as eq. (3) maps; beyond it (or without a normal) with the face
  /// of the nearest reference point. The distance is always to the nearest
  /// reference point.
  double max_line_distance_m = 0.01;

  /// InputError naming the field for a value out of range.
  void validate() const;
};

struct SurfaceAccuracyGroup {
  std::size_t vertices = 0;
  double mean_distance_m = 0.0;
  double median_distance_m = 0.0;
  double median_normal_error_rad = 0.0;  ///< 0 without vertex normals
  double p90_normal_error_rad = 0.0;
};

struct SurfaceAccuracy {
  SurfaceAccuracyGroup all, near_edges, elsewhere;
  std::size_t sharp_edges = 0;  ///< of the reference
  bool normals = false;         ///< the mesh had vertex normals (normal errors measured)
};

/// Throws InputError (source "reference mesh") for a reference without
/// faces, or a bad parameter.
SurfaceAccuracy measureSurfaceAccuracy(const TriangleMesh& mesh, const TriangleMesh& reference,
                                       const SurfaceAccuracyParameters& params = {});

/// Compact JSON (sorted keys; lengths in metres, angles in degrees).
std::string surfaceAccuracyJson(const SurfaceAccuracy& accuracy);

/// One line of surface.jsonl: {"dataset", "raw": {...}, "filtered": {...}}
/// (surfaceAccuracyJson of each mesh against the CAD mesh).
std::string datasetSurfaceAccuracyJson(const std::string& dataset, const TriangleMesh& cad, const TriangleMesh& raw,
                                       const TriangleMesh& filtered, const SurfaceAccuracyParameters& params = {});

/// surface.md: one row per dataset and mesh (mean distance mm, median
/// normal error near edges and elsewhere, deg).
std::string surfaceAccuracyMarkdown(const std::vector<std::string>& jsonl_lines);

}  // namespace icrkit::eval
