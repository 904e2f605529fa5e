#pragma once
/// \file
/// PCL's PCD, versions 0.6/0.7: DATA ascii, binary and binary_compressed
/// (LZF). Fields x y z, normal_x normal_y normal_z, rgb/rgba become
/// positions, normals, colours; other single-count fields become attributes.
/// Points with a non-finite coordinate (organised clouds mark invalid pixels
/// with NaN) are dropped, as PCL's removeNaNFromPointCloud does.

#include <icrkit/core/io/geometry_io.hpp>

#include <ostream>
#include <string>
#include <string_view>

namespace icrkit::io {

PointCloud parsePcd(std::string_view bytes, const std::string& source);
/// Writes DATA binary or ascii (binary_compressed is read, never written).
void writePcd(std::ostream& out, const PointCloud& cloud, const WriteOptions& options = {});

}  // namespace icrkit::io
