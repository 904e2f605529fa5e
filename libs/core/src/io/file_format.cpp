#include <icrkit/core/error.hpp>
#include <icrkit/core/io/file_format.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace icrkit::io {

FileFormat formatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ply") return FileFormat::Ply;
  if (ext == ".obj") return FileFormat::Obj;
  if (ext == ".pcd") return FileFormat::Pcd;
  if (ext == ".xyz") return FileFormat::Xyz;
  throw InputError(path, "", "unknown file extension '" + ext + "', expected .ply, .obj, .pcd or .xyz");
}

const char* formatName(FileFormat format) {
  switch (format) {
    case FileFormat::Ply: return "ply";
    case FileFormat::Obj: return "obj";
    case FileFormat::Pcd: return "pcd";
    case FileFormat::Xyz: return "xyz";
  }
  return "?";
}

bool formatHoldsFaces(FileFormat format) { return format == FileFormat::Ply || format == FileFormat::Obj; }

}  // namespace icrkit::io
