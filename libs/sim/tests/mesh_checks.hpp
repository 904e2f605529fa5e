#pragma once
// Properties of closed triangle meshes that the sim tests check: Euler
// characteristic, enclosed volume, vertex-manifoldness, face areas.

#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <map>
#include <vector>

namespace icrkit::sim::test {

/// V - E + F over the vertices that faces use (2 - 2g for a closed surface of genus g).
inline long eulerCharacteristic(const TriangleMesh& mesh) {
  std::vector<char> used(mesh.vertexCount(), 0);
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) used[f[k]] = 1;
  long v = 0;
  for (char u : used) v += u;
  return v - static_cast<long>(edgeStatistics(mesh).edges) + static_cast<long>(mesh.faceCount());
}

/// Enclosed volume by the divergence theorem (m^3): positive for a closed
/// surface wound counter-clockwise seen from outside.
inline double signedVolume(const TriangleMesh& mesh) {
  const auto& p = mesh.vertices.positions;
  double six_v = 0.0;
  for (const Triangle& f : mesh.faces) six_v += p[f[0]].dot(p[f[1]].cross(p[f[2]]));
  return six_v / 6.0;
}

/// Vertices whose faces do not form one closed fan (a disc around the
/// vertex): two cones touching at a point, or a vertex on a boundary.
inline std::size_t nonManifoldVertices(const TriangleMesh& mesh) {
  std::vector<std::vector<std::pair<int, int>>> link(mesh.vertexCount());
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) link[f[k]].emplace_back(f[(k + 1) % 3], f[(k + 2) % 3]);
  std::size_t bad = 0;
  for (const auto& edges : link) {
    if (edges.empty()) continue;
    std::map<int, int> next;
    bool ok = true;
    for (const auto& [a, b] : edges) ok = next.emplace(a, b).second && ok;
    if (ok) {
      // One cycle through every link vertex.
      std::size_t steps = 0;
      int at = edges.front().first;
      do {
        const auto it = next.find(at);
        if (it == next.end()) {
          ok = false;
          break;
        }
        at = it->second;
        ++steps;
      } while (at != edges.front().first && steps <= edges.size());
      ok = ok && steps == edges.size();
    }
    if (!ok) ++bad;
  }
  return bad;
}

inline double smallestFaceArea(const TriangleMesh& mesh) {
  const std::vector<double> areas = faceAreas(mesh);
  double smallest = areas.empty() ? 0.0 : areas.front();
  for (double a : areas) smallest = std::min(smallest, a);
  return smallest;
}

}  // namespace icrkit::sim::test
