#include <icrkit/eval/normal_line_mappings.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>

namespace icrkit::eval {
namespace {

constexpr const char* kSource = "normal-line mapping";

// Lexicographic (distance to the line, distance to the anchor, index):
// a total order, so the kd-tree's traversal order never shows in the answer.
struct BestCandidate {
  int vertex = -1;
  std::tuple<double, double, std::size_t> key;

  void offer(std::size_t index, double to_line, double to_point) {
    const std::tuple<double, double, std::size_t> candidate(to_line, to_point, index);
    if (vertex < 0 || candidate < key) {
      vertex = static_cast<int>(index);
      key = candidate;
    }
  }
};

}  // namespace

double medianEdgeLength(const TriangleMesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.faces.size() * 3);
  const auto& p = mesh.vertices.positions;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) lengths.push_back((p[f[k]] - p[f[(k + 1) % 3]]).norm());
  if (lengths.empty()) return 0.0;
  const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), middle, lengths.end());
  return *middle;
}

void MappingParameters::validate() const {
  if (!(std::isfinite(max_line_distance) && max_line_distance > 0.0))
    throw InputError("MappingParameters::max_line_distance", "",
                     "expected a finite length > 0 (metres), got " + std::to_string(max_line_distance));
  if (neighbourhood_radius && !(std::isfinite(*neighbourhood_radius) && *neighbourhood_radius > 0.0))
    throw InputError(
        "MappingParameters::neighbourhood_radius", "",
        "expected a finite length > 0 (metres) or unset (automatic), got " + std::to_string(*neighbourhood_radius));
}

MappingTarget::MappingTarget(const TriangleMesh& mesh, const MappingParameters& params)
    : mesh_(&mesh),
      caster_(mesh),
      tree_(mesh.vertices.positions),
      radius_(params.neighbourhood_radius.value_or(0.0)),
      max_line_distance_(params.max_line_distance) {
  params.validate();
  if (mesh.faces.empty()) throw InputError(kSource, "target mesh", "the target mesh has no faces");
  // Vertices that no face uses (points ball pivoting left unmeshed) are not
  // part of the surface: the mappings never choose them.
  in_surface_ = referencedVertices(mesh);
  if (!params.neighbourhood_radius) radius_ = 2.0 * medianEdgeLength(mesh);
  if (!(radius_ > 0.0))
    throw InputError(kSource, "target mesh", "its median edge length is 0, so no neighbourhood radius exists; give one");
}

void MappingTarget::candidates(const Eigen::Vector3d& surface_point, int face, std::vector<std::size_t>& out) const {
  tree_.indicesWithinRadius(surface_point, radius_, out);
  out.erase(std::remove_if(out.begin(), out.end(), [&](std::size_t v) { return in_surface_[v] == 0; }), out.end());
  // A crossed face larger than the radius still offers its own corners.
  if (face >= 0)
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<std::size_t>(mesh_->faces[static_cast<std::size_t>(face)][k]));
}

CadToScanMapping::CadToScanMapping(const TriangleMesh& scan_mesh, const MappingParameters& params)
    : target_(scan_mesh, params) {}

VertexImage CadToScanMapping::map(const Eigen::Vector3d& cad_point, const Eigen::Vector3d& cad_normal) const {
  const double length = cad_normal.norm();
  if (!(length > 0.0) || !std::isfinite(length) || !cad_point.allFinite()) return {};
  const Eigen::Vector3d direction = cad_normal / length;
  const double reach = target_.maxLineDistance();

  // Nearest crossing within reach of a face turned the way of the CAD normal:
  // a face turned away is the other side of a thin wall, or of the object.
  const RayHit* chosen = nullptr;
  const auto hits = target_.rayCaster().allHitsOnLine(cad_point, direction);
  for (const RayHit& hit : hits) {
    const double t = std::abs(hit.distance);
    if (t > reach || !(hit.face_normal.dot(direction) > 0.0)) continue;
    if (!chosen || t < std::abs(chosen->distance)) chosen = &hit;
  }

  VertexImage image;
  Eigen::Vector3d anchor;
  int face = -1;
  if (chosen) {
    anchor = chosen->point;
    face = chosen->face;
  } else {
    const ClosestPoint nearest = target_.rayCaster().closestPoint(cad_point, reach);
    if (!nearest.found) return image;
    anchor = nearest.point;
    face = nearest.face;
    image.fallback = true;
  }

  thread_local std::vector<std::size_t> candidates;
  target_.candidates(anchor, face, candidates);
  const auto& mesh = target_.mesh();
  const bool sided = mesh.vertices.normals.size() == mesh.vertexCount();
  BestCandidate facing, any;
  for (const std::size_t index : candidates) {
    const double to_line = direction.cross(cad_point - mesh.vertices.positions[index]).norm();
    const double to_anchor = (anchor - mesh.vertices.positions[index]).norm();
    any.offer(index, to_line, to_anchor);
    if (sided && mesh.vertices.normals[index].dot(direction) > 0.0) facing.offer(index, to_line, to_anchor);
  }
  const BestCandidate& best = facing.vertex >= 0 ? facing : any;
  image.vertex = best.vertex;
  image.line_distance_m = std::get<0>(best.key);
  return image;
}

std::vector<VertexImage> CadToScanMapping::mapVertices(const TriangleMesh& cad, const std::vector<int>& vertices) const {
  if (cad.vertices.normals.size() != cad.vertexCount())
    throw InputError(kSource, "CAD mesh", "the CAD mesh needs one normal per vertex");
  std::vector<VertexImage> images(vertices.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const int v = vertices[i];
      if (v < 0 || static_cast<std::size_t>(v) >= cad.vertexCount())
        throw InputError(kSource, "CAD vertex " + std::to_string(v),
                         "index out of range for " + std::to_string(cad.vertexCount()) + " vertices");
      images[i] = map(cad.vertices.positions[static_cast<std::size_t>(v)], cad.vertices.normals[static_cast<std::size_t>(v)]);
    }
  });
  return images;
}

ScanToCadMapping::ScanToCadMapping(const TriangleMesh& cad_mesh, const MappingParameters& params)
    : target_(cad_mesh, params) {
  if (cad_mesh.vertices.normals.size() != cad_mesh.vertexCount())
    throw InputError(kSource, "CAD mesh", "the CAD mesh needs one normal per vertex");
}

VertexImage ScanToCadMapping::map(const Eigen::Vector3d& scan_point, const Eigen::Vector3d& scan_normal) const {
  VertexImage image;
  if (!scan_point.allFinite()) return image;
  const auto& mesh = target_.mesh();
  const auto& positions = mesh.vertices.positions;
  const auto& normals = mesh.vertices.normals;
  const bool sided = scan_normal.allFinite() && scan_normal.squaredNorm() > 0.0;
  const double reach = target_.maxLineDistance();

  // With the scan normal known, the anchor is where a finger approaching
  // along it touches the CAD surface: the nearest crossing of the line with
  // a CAD face turned the same way (its vertices' normals). The nearest CAD
  // point alone can lie on the far side of a thin wall (a cup's inner
  // surface), whose vertices all face away.
  ClosestPoint nearest;
  if (sided) {
    const Eigen::Vector3d direction = scan_normal.normalized();
    double best = std::numeric_limits<double>::infinity();
    for (const RayHit& hit : target_.rayCaster().allHitsOnLine(scan_point, direction)) {
      const double t = std::abs(hit.distance);
      if (t > reach || t >= best) continue;
      const auto& f = mesh.faces[static_cast<std::size_t>(hit.face)];
      const Eigen::Vector3d face_normal = normals[static_cast<std::size_t>(f[0])] +
                                          normals[static_cast<std::size_t>(f[1])] +
                                          normals[static_cast<std::size_t>(f[2])];
      if (!(face_normal.dot(direction) > 0.0)) continue;
      best = t;
      nearest.found = true;
      nearest.point = hit.point;
      nearest.face = hit.face;
    }
  }
  if (!nearest.found) {
    nearest = target_.rayCaster().closestPoint(scan_point, reach);
    if (!nearest.found) return image;
    image.fallback = sided;
  }

  thread_local std::vector<std::size_t> candidates;
  target_.candidates(nearest.point, nearest.face, candidates);
  BestCandidate facing, any;
  for (const std::size_t index : candidates) {
    const Eigen::Vector3d offset = scan_point - positions[index];
    const double to_line = normals[index].cross(offset).norm() / std::max(normals[index].norm(), 1e-300);
    const double to_point = (nearest.point - positions[index]).norm();
    any.offer(index, to_line, to_point);
    if (sided && normals[index].dot(scan_normal) > 0.0) facing.offer(index, to_line, to_point);
  }
  const BestCandidate& best = facing.vertex >= 0 ? facing : any;
  image.vertex = best.vertex;
  image.line_distance_m = std::get<0>(best.key);
  return image;
}

std::vector<VertexImage> ScanToCadMapping::mapVertices(const TriangleMesh& scan, const std::vector<int>& vertices) const {
  const bool with_normals = scan.vertices.normals.size() == scan.vertexCount();
  std::vector<VertexImage> images(vertices.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const int v = vertices[i];
      if (v < 0 || static_cast<std::size_t>(v) >= scan.vertexCount())
        throw InputError(kSource, "scan vertex " + std::to_string(v),
                         "index out of range for " + std::to_string(scan.vertexCount()) + " vertices");
      const auto u = static_cast<std::size_t>(v);
      images[i] = map(scan.vertices.positions[u], with_normals ? scan.vertices.normals[u] : Eigen::Vector3d::Zero());
    }
  });
  return images;
}

}  // namespace icrkit::eval
