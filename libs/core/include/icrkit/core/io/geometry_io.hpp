#pragma once
/// \file
/// Reading and writing meshes and clouds in any supported format.
///
/// Readers throw InputError (file, line or element, what was expected) on
/// malformed input; writers write to a temporary file in the target
/// directory and rename it into place, so an output is never half-written.

#include <icrkit/core/attributes.hpp>
#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <string>

namespace icrkit::io {

enum class Encoding { Binary, Ascii };

struct WriteOptions {
  Encoding encoding = Encoding::Binary;  ///< PLY and PCD; OBJ and XYZ are always text
  /// Type of positions and normals in PLY/PCD. Float64 keeps every bit of
  /// the in-memory doubles; Float32 halves the size.
  ScalarType real_type = ScalarType::Float64;
  bool big_endian = false;  ///< binary PLY only
};

/// Reads any format; point formats (PCD, XYZ) give a mesh without faces.
TriangleMesh readTriangleMesh(const std::string& path);
/// Reads any format and keeps the vertices only.
PointCloud readPointCloud(const std::string& path);

/// Writes PLY or OBJ; a point-only format (PCD, XYZ) gets an InputError
/// when the mesh has faces (use writePointCloud to drop them deliberately).
void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options = {});
void writePointCloud(const std::string& path, const PointCloud& cloud, const WriteOptions& options = {});

/// The whole file as bytes; InputError when it cannot be opened or read.
std::string readFileBytes(const std::string& path);

}  // namespace icrkit::io
