#pragma once
/// \file
/// Stanford PLY: ASCII, binary little and big endian, any scalar type, list
/// properties. Vertex properties other than x/y/z, nx/ny/nz and
/// red/green/blue become named attributes; faces (`vertex_indices` or
/// `vertex_index`) are fan-triangulated; other elements (e.g. the Stanford
/// scans' `range_grid`) are skipped.

#include <icrkit/core/io/geometry_io.hpp>

#include <ostream>
#include <string>
#include <string_view>

namespace icrkit::io {

/// `source` names the data in errors (normally the file path).
TriangleMesh parsePly(std::string_view bytes, const std::string& source);
void writePly(std::ostream& out, const PointCloud& vertices, const std::vector<Triangle>& faces,
              const WriteOptions& options = {});

}  // namespace icrkit::io
