// Geometry files: the byte parsers behind io::readTriangleMesh and
// io::readPointCloud, fed directly (no file needed).
#include "fuzz_targets.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/obj.hpp>
#include <icrkit/core/io/pcd.hpp>
#include <icrkit/core/io/ply.hpp>
#include <icrkit/core/io/xyz.hpp>

#include <sstream>
#include <stdexcept>
#include <string_view>

namespace icrkit::fuzz {

namespace {

std::string_view view(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// The parser's answer to bad bytes is an InputError; what it accepts must
// be writable and read back alike (the writer sees every index and
// attribute the reader let through), so a failure there escapes as a bug.
template <typename Parse>
void parseThenRoundTrip(Parse parse) {
  TriangleMesh mesh;
  try {
    mesh = parse();
  } catch (const InputError& e) {
    rejected(e);
    return;
  }
  std::ostringstream out;
  io::writePly(out, mesh.vertices, mesh.faces);
  const TriangleMesh again = io::parsePly(out.str(), "round trip");
  if (again.vertices.size() != mesh.vertices.size() || again.faces.size() != mesh.faces.size())
    throw std::logic_error("PLY round trip changed the element counts");
}

}  // namespace

void fuzzPly(const std::uint8_t* data, std::size_t size) {
  parseThenRoundTrip([&] { return io::parsePly(view(data, size), "fuzz.ply"); });
}

void fuzzObj(const std::uint8_t* data, std::size_t size) {
  parseThenRoundTrip([&] { return io::parseObj(view(data, size), "fuzz.obj"); });
}

void fuzzPcd(const std::uint8_t* data, std::size_t size) {
  parseThenRoundTrip([&] {
    TriangleMesh mesh;
    mesh.vertices = io::parsePcd(view(data, size), "fuzz.pcd");
    return mesh;
  });
}

void fuzzXyz(const std::uint8_t* data, std::size_t size) {
  parseThenRoundTrip([&] {
    TriangleMesh mesh;
    mesh.vertices = io::parseXyz(view(data, size), "fuzz.xyz");
    return mesh;
  });
}

}  // namespace icrkit::fuzz
