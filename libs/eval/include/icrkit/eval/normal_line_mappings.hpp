#pragma once
/// \file
/// The paper's normal-line mappings between a CAD mesh and a mesh
/// reconstructed from sensor data (S), both in one frame, both along CAD
/// normals only (eqs. 2 and 3):
///
///   P_C2S(p^C) = argmin over S vertices q of || n^C x (p^C - q) ||   (eq. 2)
///   P_S2C(p^S) = argmin over CAD vertices q of || n_q x (p^S - q) ||  (eq. 3)
///
/// Taken over the whole mesh the argmin would often land on the object's far
/// side, which the same line also crosses; the argmin is therefore taken
/// among the vertices near where the line meets the near surface. The rules
/// (docs/evaluation.md):
///
/// - P_C2S: the full line through p^C along n^C is cast both ways on S
///   (Embree); the nearest crossing within `max_line_distance` of a face
///   turned the way of n^C wins (a face turned away is the other side of a
///   thin wall or of the object). The candidates are the S vertices within
///   `neighbourhood_radius` of that crossing, plus the crossed face's own
///   vertices; when S has vertex normals, candidates turned away from n^C
///   are dropped unless none is left. When no such crossing is within reach
///   (a hole in S), the surface point of S nearest to p^C within
///   `max_line_distance` stands in for the crossing (counted as a fallback).
/// - P_S2C: the CAD normal is only known once the answer is. When p^S has
///   a normal n^S, the line through p^S along n^S is cast both ways on the
///   CAD mesh and the nearest crossing within `max_line_distance` of a face
///   turned the way of n^S (by its vertices' normals) is the anchor: where
///   a finger approaching along -n^S touches the true surface. Otherwise
///   (no normal, or no such crossing: counted as a fallback) the CAD
///   surface point nearest to p^S within `max_line_distance` is. The
///   candidates are the CAD vertices within `neighbourhood_radius` of the
///   anchor plus its face's vertices; with n^S, those whose CAD normal
///   faces the other way are dropped unless none is left. The crossing
///   matters on thin walls: the nearest CAD point of a cup's outer wall
///   seen with 1-2 mm noise is often on the inner wall, all of whose
///   vertices face away (docs/evaluation.md).
///
/// Vertices used by no face (points left unmeshed) are never chosen.
///
/// Ties break on the distance to the crossing (or nearest surface point),
/// then the lower index, so
/// every answer is a deterministic function of the meshes.

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/ray_caster.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace icrkit::eval {

struct MappingParameters {
  /// Radius (metres, finite and > 0) around the line's crossing within
  /// which target vertices compete; unset: twice the target's median edge
  /// length.
  std::optional<double> neighbourhood_radius;
  /// Crossings and nearest surface points farther than this (metres) from the
  /// mapped point are ignored: a reconstruction lies within millimetres of
  /// the CAD surface, the far side of a graspable object is centimetres away.
  double max_line_distance = 0.01;

  /// Throws InputError naming the field ("MappingParameters::max_line_distance",
  /// "MappingParameters::neighbourhood_radius") for a length out of range.
  void validate() const;
};

struct VertexImage {
  int vertex = -1;               ///< target vertex; -1 when nothing is within reach
  double line_distance_m = 0.0;  ///< the minimised || n x (p - q) ||
  bool fallback = false;         ///< the line crossed nothing; the nearest surface point was used
};

/// Median length of the mesh's edges (each face's three edges; 0 for no faces).
double medianEdgeLength(const TriangleMesh& mesh);

/// Shared machinery: a target mesh with its Embree scene and vertex kd-tree.
class MappingTarget {
public:
  /// Keeps a reference to `mesh` (it must outlive this). Throws InputError
  /// for a mesh without faces, or invalid parameters.
  MappingTarget(const TriangleMesh& mesh, const MappingParameters& params = {});

  const TriangleMesh& mesh() const { return *mesh_; }
  const RayCaster& rayCaster() const { return caster_; }
  double neighbourhoodRadius() const { return radius_; }
  double maxLineDistance() const { return max_line_distance_; }

  /// The candidate target vertices around a surface point on `face`: those
  /// within the neighbourhood radius that some face uses, and the face's own.
  void candidates(const Eigen::Vector3d& surface_point, int face, std::vector<std::size_t>& out) const;

private:
  const TriangleMesh* mesh_;
  RayCaster caster_;
  KdTree tree_;
  std::vector<std::uint8_t> in_surface_;  ///< per vertex: used by a face
  double radius_;
  double max_line_distance_;
};

/// P_C2S, eq. (2): CAD vertex (position, CAD normal) -> vertex of S.
class CadToScanMapping {
public:
  CadToScanMapping(const TriangleMesh& scan_mesh, const MappingParameters& params = {});

  VertexImage map(const Eigen::Vector3d& cad_point, const Eigen::Vector3d& cad_normal) const;
  /// Every vertex of `cad` (which needs normals), in parallel.
  std::vector<VertexImage> mapVertices(const TriangleMesh& cad, const std::vector<int>& vertices) const;

  const MappingTarget& target() const { return target_; }

private:
  MappingTarget target_;
};

/// P_S2C, eq. (3): point of S (with its normal, or zero when unknown) -> CAD
/// vertex. The CAD mesh needs one unit normal per vertex.
class ScanToCadMapping {
public:
  ScanToCadMapping(const TriangleMesh& cad_mesh, const MappingParameters& params = {});

  VertexImage map(const Eigen::Vector3d& scan_point, const Eigen::Vector3d& scan_normal = Eigen::Vector3d::Zero()) const;
  /// The given vertices of `scan` (its normals used when present), in parallel.
  std::vector<VertexImage> mapVertices(const TriangleMesh& scan, const std::vector<int>& vertices) const;

  const MappingTarget& target() const { return target_; }

private:
  MappingTarget target_;
};

}  // namespace icrkit::eval
