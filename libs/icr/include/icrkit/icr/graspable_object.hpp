#pragma once
/// \file
/// A mesh prepared for grasp analysis: vertex neighbours, the wrench frame and
/// the exclusion mask, computed once and shared by every grasp on it.

#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/wrench.hpp>

#include <cstdint>
#include <vector>

namespace icrkit::icr {

class GraspableObject {
public:
  /// Keeps a reference to `mesh` (it must outlive the object). The mesh needs
  /// one outward unit normal per vertex; `excluded` is empty or one flag per
  /// vertex (non-zero: the vertex can never be a contact or join a region).
  /// Throws InputError on a mesh without normals, a zero normal or a mask of
  /// the wrong size.
  GraspableObject(const TriangleMesh& mesh, const WrenchFrame& frame, std::vector<std::uint8_t> excluded = {});

  /// The frame origin as torque reference, lambda from the mesh vertices.
  static GraspableObject withDefaultFrame(const TriangleMesh& mesh, std::vector<std::uint8_t> excluded = {},
                                          TorqueReference reference = TorqueReference::Origin);

  const TriangleMesh& mesh() const { return *mesh_; }
  const VertexAdjacency& adjacency() const { return adjacency_; }
  const WrenchFrame& frame() const { return frame_; }
  std::size_t vertexCount() const { return mesh_->vertexCount(); }
  bool excluded(std::size_t vertex) const { return !excluded_.empty() && excluded_[vertex] != 0; }
  const std::vector<std::uint8_t>& exclusionMask() const { return excluded_; }

  const Eigen::Vector3d& position(std::size_t v) const { return mesh_->vertices.positions[v]; }
  const Eigen::Vector3d& normal(std::size_t v) const { return mesh_->vertices.normals[v]; }

private:
  const TriangleMesh* mesh_;
  VertexAdjacency adjacency_;
  WrenchFrame frame_;
  std::vector<std::uint8_t> excluded_;
};

/// The excluded flags of a mesh's `excluded` vertex attribute (set by
/// preselection), or an empty mask when the attribute is absent.
std::vector<std::uint8_t> exclusionMaskOf(const TriangleMesh& mesh);

}  // namespace icrkit::icr
