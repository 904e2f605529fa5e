#pragma once
// Meshes with known symmetry for the ICR tests, and random prototypes on them.

#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace icrkit::test {

/// A unit sphere made by projecting a cube whose faces are (n/2) x (n/2) grids of quads, each split
/// into four triangles around its centre, onto
/// the sphere: symmetric under every permutation and sign change of the axes.
/// `scale` stretches it into an ellipsoid. Vertex normals are computed.
inline TriangleMesh cubeSphere(int n, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones()) {
  TriangleMesh mesh;
  std::map<std::tuple<int, int, int>, int> index;  // integer lattice point -> vertex
  auto vertex = [&](int x, int y, int z) {
    auto key = std::make_tuple(x, y, z);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const Eigen::Vector3d p = Eigen::Vector3d(x, y, z).normalized();
    mesh.vertices.positions.push_back(p.cwiseProduct(scale));
    return index[key] = static_cast<int>(mesh.vertices.positions.size() - 1);
  };
  // Lattice coordinates run over -n..n in steps of 2 so that face centres are integers.
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1})
      for (int i = -n; i < n; i += 2)
        for (int j = -n; j < n; j += 2) {
          auto at = [&](int a, int b) {
            int c[3];
            c[axis] = sign * n;
            c[(axis + 1) % 3] = a;
            c[(axis + 2) % 3] = b;
            return vertex(c[0], c[1], c[2]);
          };
          // Four triangles around the quad centre: a diagonal split would break
          // the mirror symmetry of the triangulation (and of the normals).
          const int v00 = at(i, j), v10 = at(i + 2, j), v11 = at(i + 2, j + 2), v01 = at(i, j + 2);
          const int centre = at(i + 1, j + 1);
          mesh.faces.emplace_back(centre, v00, v10);
          mesh.faces.emplace_back(centre, v10, v11);
          mesh.faces.emplace_back(centre, v11, v01);
          mesh.faces.emplace_back(centre, v01, v00);
        }
  computeVertexNormals(mesh);
  return mesh;
}

/// Index of the vertex nearest to p.
inline int nearestVertex(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  int best = -1;
  double best_distance = 1e300;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const double d = (mesh.vertices.positions[v] - p).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(v);
    }
  }
  return best;
}

/// A random force-closure grasp of distinct vertices with epsilon above
/// `min_epsilon` (draws from `rng`, which callers keep using), or none after
/// `attempts` draws.
inline std::vector<int> randomForceClosureGrasp(const icr::GraspableObject& object, const icr::ContactModel& model,
                                                std::size_t fingers, double min_epsilon, std::mt19937& rng,
                                                int attempts = 20000) {
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(object.vertexCount()) - 1);
  for (int attempt = 0; attempt < attempts; ++attempt) {
    std::set<int> distinct;
    while (distinct.size() < fingers) distinct.insert(vertex(rng));
    std::vector<int> contacts(distinct.begin(), distinct.end());
    std::shuffle(contacts.begin(), contacts.end(), rng);
    const icr::GraspWrenchSpace gws = icr::graspWrenchSpace(object, contacts, model);
    if (gws.force_closure && gws.epsilon > min_epsilon) return contacts;
  }
  return {};
}

}  // namespace icrkit::test
