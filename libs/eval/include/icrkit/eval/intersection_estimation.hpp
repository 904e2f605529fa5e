#pragma once
/// \file
/// Algorithm 2 of the paper (intersection estimation for one region C_n^S)
/// and the false-positive area of that region.
///
/// For each vertex p^S of C_n^S: p^C = P_S2C(p^S) (eq. 3); the line through
/// p^S parallel to the CAD normal at p^C is cast both ways against the
/// triangles of C_n^C only (those whose three vertices are in the region,
/// the same triangles that make up A(C_n^C)); every triangle it crosses or
/// touches (edges and corners count, so a line through a vertex collects
/// every region face around it) within the mapping's `max_line_distance`
/// joins I_n. Int = A(I_n) / A(C_n^C). Embree finds where the line meets
/// the CAD surface; the region faces sharing a corner with the face met
/// there are tested exactly in double precision.
///
/// False positives: a vertex of C_n^S is "outside" when its line crosses no
/// triangle of C_n^C (or it maps nowhere). Each triangle of C_n^S carries its
/// area in thirds, one to each corner; FP = the area carried by outside
/// corners, i.e. sum over region triangles of area * (outside corners) / 3,
/// reported as a percentage of A(C_n^C) like Int (docs/evaluation.md).

#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/normal_line_mappings.hpp>

#include <cstdint>
#include <vector>

namespace icrkit::eval {

struct RegionIntersection {
  std::vector<int> intersection_faces;     ///< I_n: CAD face indices, sorted
  double cad_region_area_m2 = 0.0;         ///< A(C_n^C)
  double intersection_area_m2 = 0.0;       ///< A(I_n)
  double scan_region_area_m2 = 0.0;        ///< A(C_n^S), on the reconstructed mesh
  double false_positive_area_m2 = 0.0;
  std::vector<int> mapped_vertices;        ///< P_S2C of each C_n^S vertex, in its order (-1: unmapped)
  std::vector<std::uint8_t> inside;        ///< per C_n^S vertex: its line crossed C_n^C
  std::size_t unmapped = 0;
};

class IntersectionEstimator {
public:
  /// Keeps a reference to `cad` (one unit normal per vertex) and builds the
  /// CAD side of P_S2C once; estimate() is const and thread-safe.
  explicit IntersectionEstimator(const TriangleMesh& cad, const MappingParameters& params = {});

  /// Throws InputError for an out-of-range vertex in either region.
  RegionIntersection estimate(const std::vector<int>& cad_region, const TriangleMesh& scan,
                              const std::vector<int>& scan_region) const;
  /// The same with the scan's vertexFaces() computed once by the caller, so
  /// that a call costs the regions' size rather than the scan mesh's.
  RegionIntersection estimate(const std::vector<int>& cad_region, const TriangleMesh& scan,
                              const VertexFaces& scan_faces, const std::vector<int>& scan_region) const;

  const ScanToCadMapping& scanToCad() const { return mapping_; }
  const std::vector<double>& cadFaceAreas() const { return cad_face_areas_; }

private:
  const TriangleMesh* cad_;
  ScanToCadMapping mapping_;
  std::vector<double> cad_face_areas_;
  VertexFaces cad_faces_of_vertex_;
};

/// Faces whose three vertices are all flagged in `vertex_in_region`.
std::vector<std::uint8_t> regionFaceMask(const TriangleMesh& mesh, const std::vector<std::uint8_t>& vertex_in_region);

}  // namespace icrkit::eval
