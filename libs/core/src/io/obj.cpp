// Wavefront OBJ reader and writer.
//
// OBJ attaches normals to face corners, icrkit to vertices. The reader
// remembers which normals each vertex was given and resolves them once the
// whole file is read (see resolveVertexNormals).

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/obj.hpp>

#include "io/text_scanner.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::io {
namespace {

using detail::TextScanner;

// One corner's reference to a normal, kept until the end of the file.
struct NormalUse {
  int vertex;
  int normal;
  bool operator<(const NormalUse& o) const { return vertex != o.vertex ? vertex < o.vertex : normal < o.normal; }
  bool operator==(const NormalUse& o) const { return vertex == o.vertex && normal == o.normal; }
};

bool isComment(std::string_view token) { return !token.empty() && token.front() == '#'; }

// Reads the coordinates of a `v` or `vn` statement; further columns (w,
// vertex colours) are left for the caller to skip.
Eigen::Vector3d readTriple(TextScanner& scanner, const char* statement) {
  Eigen::Vector3d value;
  for (int k = 0; k < 3; ++k) {
    const std::string_view token = scanner.nextTokenOnLine();
    if (token.empty() || isComment(token))
      scanner.fail(std::string("'") + statement + "' has " + std::to_string(k) + " numbers, expected 3");
    if (!detail::parseNumber(token, value[k]))
      scanner.fail(std::string("expected a number in '") + statement + "', found '" + TextScanner::clip(token) +
                   "'");
    if (!std::isfinite(value[k]))
      scanner.fail(std::string("'") + statement + "' has the coordinate '" + TextScanner::clip(token) +
                   "', expected a finite number");
  }
  return value;
}

// Turns a 1-based or negative (relative) OBJ index into a 0-based one,
// checked against the `count` elements defined so far.
int resolveIndex(const TextScanner& scanner, std::string_view text, std::size_t count, const char* what,
                 std::string_view corner) {
  long long index = 0;
  if (!detail::parseNumber(text, index))
    scanner.fail(std::string("expected a ") + what + " index in face corner '" + TextScanner::clip(corner) + "'");
  long long resolved = -1;
  if (index > 0) resolved = index - 1;
  else if (index < 0) resolved = static_cast<long long>(count) + index;
  if (index == 0 || resolved < 0 || resolved >= static_cast<long long>(count))
    scanner.fail(std::string("face corner '") + TextScanner::clip(corner) + "' refers to " + what + " " +
                 std::to_string(index) + ", expected 1.." + std::to_string(count) + " or -1..-" +
                 std::to_string(count) + (count == 0 ? std::string(" (none defined yet)") : std::string()));
  return static_cast<int>(resolved);
}

// A vertex used with one normal gets it exactly as stored (the reference ICR
// data relies on that); a vertex on a crease, used with several different
// normals, gets the normalised mean of the distinct directions, each counted
// once so that the triangulation of a side does not tilt the result.
void resolveVertexNormals(std::vector<NormalUse>& uses, const std::vector<Eigen::Vector3d>& normals,
                          std::vector<Eigen::Vector3d>& result) {
  std::sort(uses.begin(), uses.end());
  uses.erase(std::unique(uses.begin(), uses.end()), uses.end());
  std::vector<Eigen::Vector3d> distinct;
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin;
    distinct.clear();
    for (; end < uses.size() && uses[end].vertex == uses[begin].vertex; ++end) {
      const Eigen::Vector3d& n = normals[static_cast<std::size_t>(uses[end].normal)];
      if (std::find(distinct.begin(), distinct.end(), n) == distinct.end()) distinct.push_back(n);
    }
    Eigen::Vector3d& target = result[static_cast<std::size_t>(uses[begin].vertex)];
    if (distinct.size() == 1) {
      target = distinct.front();
    } else {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& n : distinct) sum += n.normalized();
      // Opposite normals cancel; the first one is then as good as any.
      target = sum.norm() > 1e-12 ? Eigen::Vector3d(sum.normalized()) : distinct.front();
    }
    begin = end;
  }
}

}  // namespace

TriangleMesh parseObj(std::string_view text, const std::string& source) {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> normals;
  std::vector<NormalUse> normal_uses;
  std::size_t texture_coordinates = 0;
  std::vector<std::pair<int, int>> corners;  // vertex, normal (-1 when none)
  TextScanner scanner(text, source);

  while (true) {
    const std::string_view keyword = scanner.nextToken();
    if (keyword.empty()) break;
    if (keyword == "v") {
      mesh.vertices.positions.push_back(readTriple(scanner, "v"));
      if (mesh.vertices.positions.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        scanner.fail("too many vertices for 32-bit face indices");
    } else if (keyword == "vn") {
      normals.push_back(readTriple(scanner, "vn"));
    } else if (keyword == "vt") {
      ++texture_coordinates;
    } else if (keyword == "f") {
      corners.clear();
      const std::size_t vertex_count = mesh.vertices.positions.size();
      for (std::string_view corner = scanner.nextTokenOnLine(); !corner.empty() && !isComment(corner);
           corner = scanner.nextTokenOnLine()) {
        // a, a/b, a//c, a/b/c
        const std::size_t slash1 = corner.find('/');
        const std::string_view v_text = corner.substr(0, slash1);
        const int vertex = resolveIndex(scanner, v_text, vertex_count, "vertex", corner);
        int normal = -1;
        if (slash1 != std::string_view::npos) {
          const std::size_t slash2 = corner.find('/', slash1 + 1);
          const std::string_view t_text = corner.substr(slash1 + 1, slash2 == std::string_view::npos
                                                                        ? std::string_view::npos
                                                                        : slash2 - slash1 - 1);
          if (!t_text.empty()) resolveIndex(scanner, t_text, texture_coordinates, "texture coordinate", corner);
          else if (slash2 == std::string_view::npos)
            scanner.fail("face corner '" + TextScanner::clip(corner) + "' has an empty texture index");
          if (slash2 != std::string_view::npos) {
            const std::string_view n_text = corner.substr(slash2 + 1);
            if (n_text.empty() || n_text.find('/') != std::string_view::npos)
              scanner.fail("face corner '" + TextScanner::clip(corner) +
                           "' is malformed, expected a, a/b, a//c or a/b/c");
            normal = resolveIndex(scanner, n_text, normals.size(), "normal", corner);
          }
        }
        corners.emplace_back(vertex, normal);
      }
      if (corners.size() < 3)
        scanner.fail("face has " + std::to_string(corners.size()) + " corners, expected at least 3");
      for (const auto& [vertex, normal] : corners)
        if (normal >= 0) normal_uses.push_back(NormalUse{vertex, normal});
      // A fan keeps the winding and is exact for the convex polygons that
      // exporters produce.
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        mesh.faces.emplace_back(corners[0].first, corners[k].first, corners[k + 1].first);
    }
    // Anything else (comments, o, g, s, usemtl, mtllib, l, p, ...) is skipped.
    scanner.restOfLine();
  }

  std::vector<Eigen::Vector3d>& vertex_normals = mesh.vertices.normals;
  if (!normal_uses.empty()) {
    // Vertices that no face gives a normal keep zero: there is nothing to
    // derive a direction from, and an invented one would look trustworthy.
    vertex_normals.assign(mesh.vertices.size(), Eigen::Vector3d::Zero());
    resolveVertexNormals(normal_uses, normals, vertex_normals);
  } else if (!normals.empty() && normals.size() == mesh.vertices.size()) {
    // Point-only OBJ files (and some exporters) pair `vn` with `v` by order.
    vertex_normals = std::move(normals);
  }
  return mesh;
}

void writeObj(std::ostream& out, const PointCloud& vertices, const std::vector<Triangle>& faces) {
  const std::size_t n = vertices.size();
  const bool with_normals = vertices.hasNormals();
  if (with_normals && vertices.normals.size() != n)
    throw std::invalid_argument("writeObj: " + std::to_string(vertices.normals.size()) + " normals for " +
                                std::to_string(n) + " vertices");
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (faces[f][k] < 0 || static_cast<std::size_t>(faces[f][k]) >= n)
        throw std::invalid_argument("writeObj: face " + std::to_string(f) + " refers to vertex " +
                                    std::to_string(faces[f][k]) + " of " + std::to_string(n));

  std::string buffer;
  constexpr std::size_t kFlushSize = 1 << 20;
  buffer.reserve(kFlushSize + 256);
  auto flushIfFull = [&] {
    if (buffer.size() >= kFlushSize) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  };
  auto appendVector = [&](const char* statement, const Eigen::Vector3d& value) {
    buffer += statement;
    for (int k = 0; k < 3; ++k) {
      buffer += ' ';
      detail::appendRoundTrip(buffer, value[k]);
    }
    buffer += '\n';
    flushIfFull();
  };
  for (const Eigen::Vector3d& p : vertices.positions) appendVector("v", p);
  if (with_normals)
    for (const Eigen::Vector3d& normal : vertices.normals) appendVector("vn", normal);
  char number[16];
  for (const Triangle& face : faces) {
    buffer += 'f';
    for (int k = 0; k < 3; ++k) {
      auto [end, ec] = std::to_chars(number, number + sizeof number, face[k] + 1);
      (void)ec;
      buffer += ' ';
      buffer.append(number, end);
      if (with_normals) {
        buffer += "//";
        buffer.append(number, end);
      }
    }
    buffer += '\n';
    flushIfFull();
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace icrkit::io
