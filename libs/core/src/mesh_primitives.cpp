#include <icrkit/core/mesh_primitives.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace icrkit {

TriangleMesh makeIcosphere(int subdivisions, double radius, const Eigen::Vector3d& centre) {
  if (subdivisions < 0 || subdivisions > 9)
    throw std::invalid_argument("makeIcosphere: subdivisions must be in 0..9, got " + std::to_string(subdivisions));
  if (!(radius > 0) || !std::isfinite(radius))
    throw std::invalid_argument("makeIcosphere: the radius must be positive, got " + std::to_string(radius));
  TriangleMesh mesh;
  auto& p = mesh.vertices.positions;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(-1, g, 0), Eigen::Vector3d(1, g, 0), Eigen::Vector3d(-1, -g, 0),
                                   Eigen::Vector3d(1, -g, 0), Eigen::Vector3d(0, -1, g), Eigen::Vector3d(0, 1, g),
                                   Eigen::Vector3d(0, -1, -g), Eigen::Vector3d(0, 1, -g), Eigen::Vector3d(g, 0, -1),
                                   Eigen::Vector3d(g, 0, 1), Eigen::Vector3d(-g, 0, -1), Eigen::Vector3d(-g, 0, 1)})
    p.push_back(v.normalized());
  mesh.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
                {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;  // an edge shared by two faces is split once
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      p.push_back((p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]).normalized());
      return midpoints[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<Triangle> finer;
    finer.reserve(mesh.faces.size() * 4);
    for (const Triangle& f : mesh.faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    mesh.faces = std::move(finer);
  }
  mesh.vertices.normals = p;
  for (Eigen::Vector3d& v : p) v = centre + radius * v;
  return mesh;
}

}  // namespace icrkit
