#pragma once
/// \file
/// Wavefront OBJ: `v`, `vn`, `f` with `a`, `a/b`, `a//c`, `a/b/c`, negative
/// (relative) indices; polygons are fan-triangulated. Other statements
/// (`vt`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, ...) are ignored.
///
/// Normals are per vertex in icrkit: a vertex referenced with several
/// different normals gets their normalised mean.

#include <icrkit/core/io/geometry_io.hpp>

#include <ostream>
#include <string>
#include <string_view>

namespace icrkit::io {

TriangleMesh parseObj(std::string_view text, const std::string& source);
/// Writes `v` (and `vn`, faces `a//a` when there are normals) with round-trip precision.
void writeObj(std::ostream& out, const PointCloud& vertices, const std::vector<Triangle>& faces);

}  // namespace icrkit::io
