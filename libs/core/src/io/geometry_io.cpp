#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/io/obj.hpp>
#include <icrkit/core/io/pcd.hpp>
#include <icrkit/core/io/ply.hpp>
#include <icrkit/core/io/xyz.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace icrkit::io {

std::string readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", std::string("cannot open the file: ") + std::strerror(errno));
  std::string bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path, "", "cannot determine the file size (not a regular file?)");
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0, std::ios::beg);
  in.read(bytes.data(), size);
  if (in.gcount() != size) throw InputError(path, "", "reading the file failed");
  return bytes;
}

TriangleMesh readTriangleMesh(const std::string& path) {
  const FileFormat format = formatFromPath(path);
  const std::string bytes = readFileBytes(path);
  switch (format) {
    case FileFormat::Ply: return parsePly(bytes, path);
    case FileFormat::Obj: return parseObj(bytes, path);
    case FileFormat::Pcd: return TriangleMesh{parsePcd(bytes, path), {}};
    case FileFormat::Xyz: return TriangleMesh{parseXyz(bytes, path), {}};
  }
  throw InputError(path, "", "unsupported format");
}

PointCloud readPointCloud(const std::string& path) { return std::move(readTriangleMesh(path).vertices); }

void writeTriangleMesh(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options) {
  const FileFormat format = formatFromPath(path);
  if (!formatHoldsFaces(format) && !mesh.faces.empty())
    throw InputError(path, "", std::string("a .") + formatName(format) +
                                   " file cannot hold faces; write a .ply or .obj, or write the vertices only");
  mesh.validate();
  if (format == FileFormat::Ply)
    writeFileAtomically(path, [&](std::ostream& out) { writePly(out, mesh.vertices, mesh.faces, options); }, true);
  else if (format == FileFormat::Obj)
    writeFileAtomically(path, [&](std::ostream& out) { writeObj(out, mesh.vertices, mesh.faces); }, false);
  else
    writePointCloud(path, mesh.vertices, options);
}

void writePointCloud(const std::string& path, const PointCloud& cloud, const WriteOptions& options) {
  const FileFormat format = formatFromPath(path);
  cloud.validate();
  switch (format) {
    case FileFormat::Ply:
      writeFileAtomically(path, [&](std::ostream& out) { writePly(out, cloud, {}, options); }, true);
      break;
    case FileFormat::Obj:
      writeFileAtomically(path, [&](std::ostream& out) { writeObj(out, cloud, {}); }, false);
      break;
    case FileFormat::Pcd:
      writeFileAtomically(path, [&](std::ostream& out) { writePcd(out, cloud, options); }, true);
      break;
    case FileFormat::Xyz:
      writeFileAtomically(path, [&](std::ostream& out) { writeXyz(out, cloud); }, false);
      break;
  }
}

}  // namespace icrkit::io
