#include <icrkit/eval/brute_force_mappings.hpp>

#include <icrkit/core/triangle_distance.hpp>

#include "line_triangle.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <tuple>

namespace icrkit::eval {
namespace {

struct Crossing {
  bool found = false;
  double t = 0.0;  // signed, along the unit direction
  int face = -1;
  Eigen::Vector3d point;
};

struct Best {
  int vertex = -1;
  std::tuple<double, double, int> key;
  void offer(int index, double to_line, double to_point) {
    const std::tuple<double, double, int> k(to_line, to_point, index);
    if (vertex < 0 || k < key) {
      vertex = index;
      key = k;
    }
  }
};

bool isCandidate(const TriangleMesh& mesh, int v, const Eigen::Vector3d& anchor, int face, double radius) {
  if (face >= 0) {
    const Triangle& f = mesh.faces[static_cast<std::size_t>(face)];
    if (f[0] == v || f[1] == v || f[2] == v) return true;
  }
  if ((mesh.vertices.positions[static_cast<std::size_t>(v)] - anchor).norm() > radius) return false;
  for (const Triangle& f : mesh.faces)  // used by some face: part of the surface
    if (f[0] == v || f[1] == v || f[2] == v) return true;
  return false;
}

}  // namespace

VertexImage bruteForceCadToScan(const TriangleMesh& scan, const Eigen::Vector3d& cad_point,
                                const Eigen::Vector3d& cad_normal, double neighbourhood_radius,
                                double max_line_distance) {
  VertexImage image;
  const Eigen::Vector3d direction = cad_normal.normalized();
  const auto& p = scan.vertices.positions;
  Crossing facing;
  for (std::size_t i = 0; i < scan.faces.size(); ++i) {
    const Triangle& f = scan.faces[i];
    double t = 0.0;
    if (!detail::lineMeetsTriangle(cad_point, direction, p[f[0]], p[f[1]], p[f[2]], 0.0, t) ||
        std::abs(t) > max_line_distance)
      continue;
    const Eigen::Vector3d normal = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    if (!(normal.dot(direction) > 0.0)) continue;
    if (!facing.found || std::abs(t) < std::abs(facing.t))
      facing = {true, t, static_cast<int>(i), cad_point + t * direction};
  }
  Crossing chosen = facing;
  if (!chosen.found) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < scan.faces.size(); ++i) {
      const Triangle& f = scan.faces[i];
      const TrianglePoint q = closestPointOnTriangle(cad_point, p[f[0]], p[f[1]], p[f[2]]);
      if (q.distance < best) {
        best = q.distance;
        chosen = {true, 0.0, static_cast<int>(i), q.point};
      }
    }
    if (!(best <= max_line_distance)) return image;
    image.fallback = true;
  }
  const bool sided = scan.vertices.normals.size() == scan.vertexCount();
  Best facing_choice, any_choice;
  for (std::size_t v = 0; v < p.size(); ++v) {
    if (!isCandidate(scan, static_cast<int>(v), chosen.point, chosen.face, neighbourhood_radius)) continue;
    const double to_line = direction.cross(cad_point - p[v]).norm();
    const double to_anchor = (chosen.point - p[v]).norm();
    any_choice.offer(static_cast<int>(v), to_line, to_anchor);
    if (sided && scan.vertices.normals[v].dot(direction) > 0.0) facing_choice.offer(static_cast<int>(v), to_line, to_anchor);
  }
  const Best& choice = facing_choice.vertex >= 0 ? facing_choice : any_choice;
  image.vertex = choice.vertex;
  image.line_distance_m = std::get<0>(choice.key);
  return image;
}

VertexImage bruteForceScanToCad(const TriangleMesh& cad, const Eigen::Vector3d& scan_point,
                                const Eigen::Vector3d& scan_normal, double neighbourhood_radius,
                                double max_line_distance) {
  VertexImage image;
  const auto& p = cad.vertices.positions;
  const bool sided = scan_normal.squaredNorm() > 0.0;
  int face = -1;
  Eigen::Vector3d anchor;
  if (sided) {  // the nearest crossing of the scan normal's line with a CAD face turned its way
    const Eigen::Vector3d direction = scan_normal.normalized();
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < cad.faces.size(); ++i) {
      const Triangle& f = cad.faces[i];
      double t = 0.0;
      if (!detail::lineMeetsTriangle(scan_point, direction, p[f[0]], p[f[1]], p[f[2]], 0.0, t) ||
          std::abs(t) > max_line_distance || std::abs(t) >= nearest)
        continue;
      const Eigen::Vector3d face_normal = cad.vertices.normals[f[0]] + cad.vertices.normals[f[1]] +
                                          cad.vertices.normals[f[2]];
      if (!(face_normal.dot(direction) > 0.0)) continue;
      nearest = std::abs(t);
      face = static_cast<int>(i);
      anchor = scan_point + t * direction;
    }
  }
  if (face < 0) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < cad.faces.size(); ++i) {
      const Triangle& f = cad.faces[i];
      const TrianglePoint q = closestPointOnTriangle(scan_point, p[f[0]], p[f[1]], p[f[2]]);
      if (q.distance < best) {
        best = q.distance;
        face = static_cast<int>(i);
        anchor = q.point;
      }
    }
    if (!(best <= max_line_distance)) return image;
    image.fallback = sided;
  }
  Best facing, any;
  for (std::size_t v = 0; v < p.size(); ++v) {
    if (!isCandidate(cad, static_cast<int>(v), anchor, face, neighbourhood_radius)) continue;
    const Eigen::Vector3d& n = cad.vertices.normals[v];
    const Eigen::Vector3d offset = scan_point - p[v];
    const double to_line = n.cross(offset).norm() / n.norm();
    const double to_anchor = (anchor - p[v]).norm();
    any.offer(static_cast<int>(v), to_line, to_anchor);
    if (sided && n.dot(scan_normal) > 0.0) facing.offer(static_cast<int>(v), to_line, to_anchor);
  }
  const Best& choice = facing.vertex >= 0 ? facing : any;
  image.vertex = choice.vertex;
  image.line_distance_m = std::get<0>(choice.key);
  return image;
}

}  // namespace icrkit::eval
