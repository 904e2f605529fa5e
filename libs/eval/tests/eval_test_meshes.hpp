#pragma once
// Meshes with known distances for the mesh-distance and Q_n tests.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace icrkit::eval::test {

/// A flat nx x ny vertex grid in the z = 0 plane with spacing `h`, vertex
/// (i, j) at index j * nx + i and position (i h, j h, 0); every square split
/// along its (i, j)-(i+1, j+1) diagonal, so that the edge graph has the axis
/// steps and that one diagonal.
inline TriangleMesh flatGrid(int nx, int ny, double h, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) {
  TriangleMesh mesh;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) mesh.vertices.positions.push_back(origin + Eigen::Vector3d(i * h, j * h, 0.0));
  auto at = [nx](int i, int j) { return j * nx + i; };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      mesh.faces.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.faces.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return mesh;
}

/// Edge-graph distance on flatGrid between vertices (i, j) steps apart
/// (in units of h): axis steps and (+1, +1) diagonals only.
inline double flatGridGraphDistance(int di, int dj, double h) {
  if ((di >= 0) == (dj >= 0) || di == 0 || dj == 0) {
    const int a = std::abs(di), b = std::abs(dj);
    const int lo = std::min(a, b), hi = std::max(a, b);
    return (hi - lo) * h + lo * std::sqrt(2.0) * h;
  }
  return (std::abs(di) + std::abs(dj)) * h;
}

/// A flat equilateral-triangle lattice in the z = 0 plane: nx x ny vertices
/// with edge length `h`, vertex (i, j) at index j * nx + i and position
/// ((i + (j odd ? 1/2 : 0)) h, j h sqrt(3)/2, 0). Every vertex inside has six
/// neighbours at 60 degrees: a graph metric with the symmetry of a hexagon.
inline TriangleMesh triangularLattice(int nx, int ny, double h) {
  TriangleMesh mesh;
  const double row = h * std::sqrt(3.0) / 2.0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      mesh.vertices.positions.emplace_back((i + (j % 2 ? 0.5 : 0.0)) * h, j * row, 0.0);
  auto at = [nx](int i, int j) { return j * nx + i; };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      if (j % 2 == 0) {
        mesh.faces.emplace_back(at(i, j), at(i + 1, j), at(i, j + 1));
        mesh.faces.emplace_back(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
      } else {
        mesh.faces.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        mesh.faces.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
    }
  return mesh;
}

/// Vertices of `mesh` within `radius` of `centre` (inclusive, up to rounding).
inline std::vector<int> verticesWithin(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double radius) {
  std::vector<int> out;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    if ((mesh.vertices.positions[v] - centre).norm() <= radius * (1.0 + 1e-9)) out.push_back(static_cast<int>(v));
  return out;
}

/// An open tube around the z axis: `around` vertices per ring, `rings`
/// rings `spacing` apart, vertex (a, r) at index r * around + a; quads split
/// along one diagonal.
inline TriangleMesh tube(int around, int rings, double radius, double spacing) {
  TriangleMesh mesh;
  const double pi = std::acos(-1.0);
  for (int r = 0; r < rings; ++r)
    for (int a = 0; a < around; ++a) {
      const double phi = 2.0 * pi * a / around;
      mesh.vertices.positions.emplace_back(radius * std::cos(phi), radius * std::sin(phi), r * spacing);
    }
  auto at = [around](int a, int r) { return r * around + (a % around); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int a = 0; a < around; ++a) {
      mesh.faces.emplace_back(at(a, r), at(a + 1, r), at(a + 1, r + 1));
      mesh.faces.emplace_back(at(a, r), at(a + 1, r + 1), at(a, r + 1));
    }
  return mesh;
}

/// A UV sphere: `rings` latitude bands, `segments` longitude steps, two pole
/// vertices; quads split into two triangles.
inline TriangleMesh uvSphere(int rings, int segments, double radius = 1.0) {
  TriangleMesh mesh;
  const double pi = std::acos(-1.0);
  mesh.vertices.positions.emplace_back(0.0, 0.0, radius);
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * pi * s / segments;
      mesh.vertices.positions.emplace_back(radius * std::sin(theta) * std::cos(phi),
                                           radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta));
    }
  }
  mesh.vertices.positions.emplace_back(0.0, 0.0, -radius);
  const int south = static_cast<int>(mesh.vertices.positions.size()) - 1;
  auto at = [segments](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.faces.emplace_back(0, at(1, s), at(1, s + 1));
    mesh.faces.emplace_back(south, at(rings - 1, s + 1), at(rings - 1, s));
  }
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      mesh.faces.emplace_back(at(r, s), at(r + 1, s), at(r + 1, s + 1));
      mesh.faces.emplace_back(at(r, s), at(r + 1, s + 1), at(r, s + 1));
    }
  return mesh;
}

/// Vertices of flatGrid(nx, ...) within `radius` steps of (ci, cj), inclusive.
inline std::vector<int> gridDisk(int nx, int ny, double ci, double cj, double radius) {
  std::vector<int> disk;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if ((i - ci) * (i - ci) + (j - cj) * (j - cj) <= radius * radius + 1e-9) disk.push_back(j * nx + i);
  return disk;
}

}  // namespace icrkit::eval::test
