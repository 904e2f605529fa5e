#include <icrkit/core/error.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <string>

namespace icrkit::icr {
namespace {

void requireFaces(const TriangleMesh& mesh) {
  if (mesh.faces.empty())
    throw InputError("mesh", "", "the mesh has no faces; grasps need a surface, not only points");
}

}  // namespace

GraspableObject::GraspableObject(const TriangleMesh& mesh, const WrenchFrame& frame, std::vector<std::uint8_t> excluded)
    : mesh_(&mesh), frame_(frame), excluded_(std::move(excluded)) {
  const std::size_t n = mesh.vertexCount();
  requireFaces(mesh);
  if (!mesh.vertices.hasNormals())
    throw InputError("mesh", "", "the mesh has no vertex normals; ICRs need one outward normal per vertex");
  referenced_ = referencedVertices(mesh);
  for (std::size_t v = 0; v < n; ++v) {
    // Unreferenced vertices are never used, so their normals may be anything.
    if (!referenced_[v]) {
      ++unreferenced_;
      continue;
    }
    const double length = mesh.vertices.normals[v].norm();
    if (!(std::abs(length - 1.0) < 1e-3))
      throw InputError("mesh", "vertex " + std::to_string(v),
                       "the vertex normal has length " + std::to_string(length) + ", expected a unit vector");
  }
  if (!excluded_.empty() && excluded_.size() != n)
    throw InputError("exclusion mask", "", "has " + std::to_string(excluded_.size()) + " entries for " +
                                               std::to_string(n) + " vertices");
  if (!(frame.lambda > 0) || !std::isfinite(frame.lambda))
    throw InputError("wrench frame", "", "lambda must be positive, got " + std::to_string(frame.lambda));
  adjacency_ = vertexAdjacency(mesh);
  boundary_.assign(n, 0);
  std::vector<std::pair<int, int>> edges;
  edges.reserve(mesh.faces.size() * 3);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = static_cast<int>(f[k]), b = static_cast<int>(f[(k + 1) % 3]);
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary_[static_cast<std::size_t>(edges[i].first)] = boundary_[static_cast<std::size_t>(edges[i].second)] = 1;
    i = j;
  }
}

GraspableObject GraspableObject::withDefaultFrame(const TriangleMesh& mesh, std::vector<std::uint8_t> excluded,
                                                  TorqueReference reference) {
  requireFaces(mesh);
  // Stray points must not move the torque reference or stretch lambda: the
  // frame is the surface's, the same as for the mesh without them.
  return GraspableObject(mesh, makeWrenchFrame(referencedPositions(mesh), reference), std::move(excluded));
}

std::vector<std::uint8_t> exclusionMaskOf(const TriangleMesh& mesh) {
  const Attribute* attribute = mesh.vertices.attributes.find("excluded");
  if (attribute == nullptr) return {};
  std::vector<std::uint8_t> mask(attribute->values.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = attribute->values[i] != 0.0 ? 1 : 0;
  return mask;
}

}  // namespace icrkit::icr
