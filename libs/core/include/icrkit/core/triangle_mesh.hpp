#pragma once
/// \file
/// An indexed triangle mesh: per-vertex data (a PointCloud) and triangles.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace icrkit {

using Triangle = Eigen::Vector3i;  ///< vertex indices, counter-clockwise seen from outside

struct TriangleMesh {
  PointCloud vertices;           ///< positions, vertex normals, colours, vertex attributes
  std::vector<Triangle> faces;

  std::size_t vertexCount() const { return vertices.size(); }
  std::size_t faceCount() const { return faces.size(); }

  /// Throws std::invalid_argument on inconsistent sizes, non-finite
  /// coordinates or a face index out of range.
  void validate() const;
};

}  // namespace icrkit
