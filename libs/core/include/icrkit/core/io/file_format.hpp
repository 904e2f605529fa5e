#pragma once
/// \file
/// Geometry file formats, chosen by file extension (case-insensitive).

#include <string>

namespace icrkit::io {

enum class FileFormat { Ply, Obj, Pcd, Xyz };

/// Throws InputError naming the path when the extension is none of
/// .ply, .obj, .pcd, .xyz.
FileFormat formatFromPath(const std::string& path);
const char* formatName(FileFormat format);
/// True for the formats that can hold faces (PLY, OBJ).
bool formatHoldsFaces(FileFormat format);

}  // namespace icrkit::io
