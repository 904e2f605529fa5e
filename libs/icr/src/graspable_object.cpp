#include <icrkit/core/error.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <cmath>
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
  boundary_ = boundaryVertices(mesh);
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
