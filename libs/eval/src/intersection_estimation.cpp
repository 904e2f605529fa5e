#include <icrkit/eval/intersection_estimation.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include "line_triangle.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace icrkit::eval {
namespace {

std::vector<std::uint8_t> membership(std::size_t vertex_count, const std::vector<int>& region, const char* what) {
  std::vector<std::uint8_t> in(vertex_count, 0);
  for (std::size_t i = 0; i < region.size(); ++i) {
    const int v = region[i];
    if (v < 0 || static_cast<std::size_t>(v) >= vertex_count)
      throw InputError("intersection estimation", std::string(what) + " element " + std::to_string(i),
                       "vertex " + std::to_string(v) + " is out of range for " + std::to_string(vertex_count) +
                           " vertices");
    in[static_cast<std::size_t>(v)] = 1;
  }
  return in;
}

// Edges and corners count: a line through a shared vertex or edge touches
// every face around it, as the paper's "triangles intersected by this line"
// requires (Embree's watertight test gives such a touch to one face only).
constexpr double kTouchTolerance = 1e-9;

double triangleArea(const TriangleMesh& mesh, const Triangle& f) {
  const auto& p = mesh.vertices.positions;
  return 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
}

}  // namespace

std::vector<std::uint8_t> regionFaceMask(const TriangleMesh& mesh, const std::vector<std::uint8_t>& vertex_in_region) {
  std::vector<std::uint8_t> mask(mesh.faces.size(), 0);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const Triangle& f = mesh.faces[i];
    mask[i] = vertex_in_region[f[0]] && vertex_in_region[f[1]] && vertex_in_region[f[2]] ? 1 : 0;
  }
  return mask;
}

IntersectionEstimator::IntersectionEstimator(const TriangleMesh& cad, const MappingParameters& params)
    : cad_(&cad), mapping_(cad, params), cad_face_areas_(faceAreas(cad)), cad_faces_of_vertex_(vertexFaces(cad)) {}

RegionIntersection IntersectionEstimator::estimate(const std::vector<int>& cad_region, const TriangleMesh& scan,
                                                   const std::vector<int>& scan_region) const {
  return estimate(cad_region, scan, vertexFaces(scan), scan_region);
}

RegionIntersection IntersectionEstimator::estimate(const std::vector<int>& cad_region, const TriangleMesh& scan,
                                                   const VertexFaces& scan_faces,
                                                   const std::vector<int>& scan_region) const {
  const TriangleMesh& cad = *cad_;
  const auto cad_in = membership(cad.vertexCount(), cad_region, "CAD region");
  const auto scan_in = membership(scan.vertexCount(), scan_region, "scan region");
  if (scan_faces.offsets.size() != scan.vertexCount() + 1)
    throw InputError("intersection estimation", "scan faces", "the vertex-face incidence is not the scan mesh's");
  const FaceMask cad_faces = regionFaceMask(cad, cad_in);

  RegionIntersection result;
  for (std::size_t i = 0; i < cad_faces.size(); ++i)
    if (cad_faces[i]) result.cad_region_area_m2 += cad_face_areas_[i];

  result.mapped_vertices.resize(scan_region.size(), -1);
  result.inside.assign(scan_region.size(), 0);
  const auto images = mapping_.mapVertices(scan, scan_region);
  const bool any_cad_face = std::any_of(cad_faces.begin(), cad_faces.end(), [](std::uint8_t f) { return f != 0; });
  const double reach = mapping_.target().maxLineDistance();
  const RayCaster& caster = mapping_.target().rayCaster();
  const auto& positions = cad.vertices.positions;
  std::vector<std::uint8_t> crossed(cad.faces.size(), 0);
  std::vector<int> seeds;
  for (std::size_t i = 0; i < scan_region.size(); ++i) {
    const int image = images[i].vertex;
    result.mapped_vertices[i] = image;
    if (image < 0) {
      ++result.unmapped;
      continue;
    }
    if (!any_cad_face) continue;
    const Eigen::Vector3d& origin = scan.vertices.positions[static_cast<std::size_t>(scan_region[i])];
    const Eigen::Vector3d direction = cad.vertices.normals[static_cast<std::size_t>(image)].normalized();
    // Where to look: the faces Embree finds the line meeting (any face),
    // and the faces at p^C, which the line passes within line_distance of
    // (Embree's single-precision test can miss a line through a vertex on
    // sliver triangles or at a hole's rim). The region's faces sharing a
    // corner with these are then tested exactly.
    seeds.clear();
    for (const RayHit& hit : caster.allHitsOnLine(origin, direction))
      if (std::abs(hit.distance) <= reach) seeds.push_back(hit.face);
    const auto mapped = static_cast<std::size_t>(image);
    seeds.insert(seeds.end(), cad_faces_of_vertex_.begin(mapped), cad_faces_of_vertex_.end(mapped));
    for (const int seed : seeds) {
      const Triangle& seed_face = cad.faces[static_cast<std::size_t>(seed)];
      for (int k = 0; k < 3; ++k) {
        const auto corner = static_cast<std::size_t>(seed_face[k]);
        for (const int* j = cad_faces_of_vertex_.begin(corner); j != cad_faces_of_vertex_.end(corner); ++j) {
          const auto face = static_cast<std::size_t>(*j);
          if (!cad_faces[face]) continue;
          const Triangle& f = cad.faces[face];
          double t = 0.0;
          if (!detail::lineMeetsTriangle(origin, direction, positions[f[0]], positions[f[1]], positions[f[2]],
                                         kTouchTolerance, t) ||
              std::abs(t) > reach)
            continue;
          crossed[face] = 1;
          result.inside[i] = 1;
        }
      }
    }
  }
  for (std::size_t i = 0; i < crossed.size(); ++i)
    if (crossed[i]) {
      result.intersection_faces.push_back(static_cast<int>(i));
      result.intersection_area_m2 += cad_face_areas_[i];
    }

  // Outside-ness per scan vertex, then each region triangle's area in
  // thirds. The region's triangles are found through its own vertices (each
  // at its lowest corner) and summed in face order, as a pass over all faces
  // would, without one.
  std::vector<std::uint8_t> outside(scan.vertexCount(), 0);
  for (std::size_t i = 0; i < scan_region.size(); ++i)
    if (!result.inside[i]) outside[static_cast<std::size_t>(scan_region[i])] = 1;
  std::vector<int> region_faces;
  for (const int v : scan_region) {
    const auto u = static_cast<std::size_t>(v);
    for (const int* j = scan_faces.begin(u); j != scan_faces.end(u); ++j) {
      const Triangle& f = scan.faces[static_cast<std::size_t>(*j)];
      if (f.minCoeff() == v && scan_in[f[0]] && scan_in[f[1]] && scan_in[f[2]]) region_faces.push_back(*j);
    }
  }
  std::sort(region_faces.begin(), region_faces.end());
  region_faces.erase(std::unique(region_faces.begin(), region_faces.end()), region_faces.end());
  for (const int face : region_faces) {
    const Triangle& f = scan.faces[static_cast<std::size_t>(face)];
    const double area = triangleArea(scan, f);
    result.scan_region_area_m2 += area;
    const int outside_corners = outside[f[0]] + outside[f[1]] + outside[f[2]];
    result.false_positive_area_m2 += area * outside_corners / 3.0;
  }
  return result;
}

}  // namespace icrkit::eval
