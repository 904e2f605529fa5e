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
  /// faces and one outward unit normal per vertex that a face uses; a vertex
  /// no face uses is not on the surface, whatever its normal (zero, garbage):
  /// it is never a contact and never joins a region, but keeps its index.
  /// `excluded` is empty or one flag per vertex (non-zero: the vertex can
  /// never be a contact or join a region). Throws InputError on a mesh
  /// without faces or normals, a used vertex without a unit normal or a mask
  /// of the wrong size.
  GraspableObject(const TriangleMesh& mesh, const WrenchFrame& frame, std::vector<std::uint8_t> excluded = {});

  /// The frame origin (or the centroid) of the vertices faces use as torque
  /// reference, lambda the largest distance of such a vertex from it.
  static GraspableObject withDefaultFrame(const TriangleMesh& mesh, std::vector<std::uint8_t> excluded = {},
                                          TorqueReference reference = TorqueReference::Origin);

  const TriangleMesh& mesh() const { return *mesh_; }
  const VertexAdjacency& adjacency() const { return adjacency_; }
  const WrenchFrame& frame() const { return frame_; }
  std::size_t vertexCount() const { return mesh_->vertexCount(); }
  bool excluded(std::size_t vertex) const { return !excluded_.empty() && excluded_[vertex] != 0; }
  const std::vector<std::uint8_t>& exclusionMask() const { return excluded_; }
  /// Whether some face uses the vertex (referencedVertices()).
  bool referenced(std::size_t vertex) const { return referenced_[vertex] != 0; }
  /// Whether the vertex lies on an edge that only one face uses (the rim of
  /// a hole or of the seen surface).
  bool onMeshBoundary(std::size_t vertex) const { return boundary_[vertex] != 0; }
  /// Vertices no face uses.
  std::size_t unreferencedCount() const { return unreferenced_; }
  /// Whether the vertex may be a contact or join a region: on the surface
  /// and not excluded.
  bool eligible(std::size_t vertex) const { return referenced(vertex) && !excluded(vertex); }

  const Eigen::Vector3d& position(std::size_t v) const { return mesh_->vertices.positions[v]; }
  const Eigen::Vector3d& normal(std::size_t v) const { return mesh_->vertices.normals[v]; }

private:
  const TriangleMesh* mesh_;
  VertexAdjacency adjacency_;
  WrenchFrame frame_;
  std::vector<std::uint8_t> excluded_;
  std::vector<std::uint8_t> referenced_;
  std::vector<std::uint8_t> boundary_;
  std::size_t unreferenced_ = 0;
};

/// The excluded flags of a mesh's `excluded` vertex attribute (set by
/// preselection), or an empty mask when the attribute is absent.
std::vector<std::uint8_t> exclusionMaskOf(const TriangleMesh& mesh);

}  // namespace icrkit::icr
