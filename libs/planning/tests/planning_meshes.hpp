#pragma once
// Meshes with known answers for the planner's tests.

#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <map>
#include <tuple>

namespace icrkit::test {

/// A flat square [0, size]^2 at z = 0, n x n quads, normals +z: an open
/// surface whose rim is its four sides.
inline TriangleMesh flatGrid(double size, int n) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      mesh.vertices.positions.emplace_back(size * i / n, size * j / n, 0.0);
      mesh.vertices.normals.emplace_back(0.0, 0.0, 1.0);
    }
  const auto at = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.faces.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.faces.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return mesh;
}

/// A closed cube [0, size]^3, each side an n x n grid sharing its border
/// vertices with the neighbouring sides, outward winding, area-weighted
/// vertex normals (so vertices on the cube's edges carry blended normals,
/// as a reconstruction's do).
inline TriangleMesh griddedCube(double size, int n) {
  TriangleMesh mesh;
  std::map<std::tuple<int, int, int>, int> index;
  const auto vertex = [&](int x, int y, int z) {
    const auto key = std::make_tuple(x, y, z);
    const auto found = index.find(key);
    if (found != index.end()) return found->second;
    const int id = static_cast<int>(mesh.vertices.positions.size());
    mesh.vertices.positions.emplace_back(size * x / n, size * y / n, size * z / n);
    index[key] = id;
    return id;
  };
  // Each side: a fixed axis at 0 or n, two running axes.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          int corner[4][3];
          const int da[4] = {0, 1, 1, 0}, db[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            corner[k][axis] = side * n;
            corner[k][(axis + 1) % 3] = a + da[k];
            corner[k][(axis + 2) % 3] = b + db[k];
          }
          int v[4];
          for (int k = 0; k < 4; ++k) v[k] = vertex(corner[k][0], corner[k][1], corner[k][2]);
          mesh.faces.emplace_back(v[0], v[1], v[2]);
          mesh.faces.emplace_back(v[0], v[2], v[3]);
        }
  computeVertexNormals(mesh);  // also turns the winding outwards
  return mesh;
}

}  // namespace icrkit::test
