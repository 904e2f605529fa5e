#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <tuple>
#include <utility>

namespace icrkit {
namespace {

struct FaceEdge {
  int a, b;  // undirected key, a < b
  int face;
  bool forward;  // the face traverses a -> b
  bool operator<(const FaceEdge& other) const { return std::tie(a, b, face) < std::tie(other.a, other.b, other.face); }
};

void flip(Triangle& f) { std::swap(f[1], f[2]); }

}  // namespace

OrientationReport orientFaces(TriangleMesh& mesh) {
  OrientationReport report;
  const std::size_t face_count = mesh.faces.size();
  if (face_count == 0) return report;

  std::vector<FaceEdge> edges;
  edges.reserve(face_count * 3);
  for (std::size_t i = 0; i < face_count; ++i)
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.faces[i][k], v = mesh.faces[i][(k + 1) % 3];
      if (u == v) continue;
      edges.push_back({std::min(u, v), std::max(u, v), static_cast<int>(i), u < v});
    }
  std::sort(edges.begin(), edges.end());

  // Face -> its manifold neighbours, with whether both traverse the shared
  // edge the same way (then one of them must flip).
  struct Link {
    int face;
    bool same_direction;
  };
  std::vector<std::vector<Link>> links(face_count);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i == 2) {
      const FaceEdge& e0 = edges[i];
      const FaceEdge& e1 = edges[i + 1];
      const bool same = e0.forward == e1.forward;
      links[e0.face].push_back({e1.face, same});
      links[e1.face].push_back({e0.face, same});
    }
    i = j;
  }

  // Breadth-first over each component: decide per face whether it flips
  // relative to the component's seed.
  std::vector<int> flipped(face_count, -1);
  std::vector<int> component(face_count, -1);
  int component_count = 0;
  std::deque<int> queue;
  for (std::size_t seed = 0; seed < face_count; ++seed) {
    if (flipped[seed] >= 0) continue;
    flipped[seed] = 0;
    component[seed] = component_count;
    queue.push_back(static_cast<int>(seed));
    while (!queue.empty()) {
      const int f = queue.front();
      queue.pop_front();
      for (const Link& link : links[f]) {
        const int wanted = link.same_direction ? 1 - flipped[f] : flipped[f];
        if (flipped[link.face] < 0) {
          flipped[link.face] = wanted;
          component[link.face] = component_count;
          queue.push_back(link.face);
        } else if (flipped[link.face] != wanted && f < link.face) {
          ++report.conflicting_edges;
        }
      }
    }
    ++component_count;
  }
  for (std::size_t i = 0; i < face_count; ++i)
    if (flipped[i] == 1) flip(mesh.faces[i]);

  // Outward per component. For a closed surface the signed volume decides;
  // for an open one (a partial view) the area-weighted normals should point
  // away from the component's centroid on average.
  const auto& p = mesh.vertices.positions;
  std::vector<Eigen::Vector3d> centroid(component_count, Eigen::Vector3d::Zero());
  std::vector<double> area(component_count, 0.0);
  for (std::size_t i = 0; i < face_count; ++i) {
    const Triangle& f = mesh.faces[i];
    const double a = 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
    centroid[component[i]] += a * (p[f[0]] + p[f[1]] + p[f[2]]) / 3.0;
    area[component[i]] += a;
  }
  for (int c = 0; c < component_count; ++c)
    if (area[c] > 0) centroid[c] /= area[c];
  std::vector<double> outwardness(component_count, 0.0);
  for (std::size_t i = 0; i < face_count; ++i) {
    const Triangle& f = mesh.faces[i];
    const Eigen::Vector3d c = centroid[component[i]];
    // Signed volume of the tetrahedron (c, a, b, c') relative to the centroid
    // is the closed-surface test and, for open patches, a weighted version of
    // "normal points away from the centroid".
    outwardness[component[i]] += (p[f[0]] - c).dot((p[f[1]] - c).cross(p[f[2]] - c));
  }
  std::vector<bool> turn(component_count);
  for (int c = 0; c < component_count; ++c) turn[c] = outwardness[c] < 0;
  for (std::size_t i = 0; i < face_count; ++i)
    if (turn[component[i]]) flip(mesh.faces[i]);

  for (std::size_t i = 0; i < face_count; ++i)
    if ((flipped[i] == 1) != turn[component[i]]) ++report.flipped_faces;
  return report;
}

OrientationReport computeVertexNormals(TriangleMesh& mesh, const VertexNormalParameters& params) {
  OrientationReport report;
  if (params.orient_faces) report = orientFaces(mesh);
  const auto& p = mesh.vertices.positions;
  std::vector<Eigen::Vector3d> normals(p.size(), Eigen::Vector3d::Zero());
  for (const Triangle& f : mesh.faces) {
    // The unnormalised cross product weights each face by twice its area.
    const Eigen::Vector3d n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    for (int k = 0; k < 3; ++k) normals[f[k]] += n;
  }
  for (Eigen::Vector3d& n : normals) {
    const double length = n.norm();
    n = length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
  }
  // A zero normal on an unreferenced vertex would make the mesh fail any
  // later unit-normal check (ours skip such vertices, other tools do not).
  const std::vector<std::uint8_t> referenced = referencedVertices(mesh);
  std::vector<Eigen::Vector3d> donor_positions;
  std::vector<std::size_t> donors;
  bool borrowing = false;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    if (!referenced[v]) {
      borrowing = true;
    } else if (normals[v] != Eigen::Vector3d::Zero()) {
      donor_positions.push_back(p[v]);
      donors.push_back(v);
    }
  }
  if (borrowing && !donors.empty()) {
    const KdTree tree(donor_positions);
    for (std::size_t v = 0; v < normals.size(); ++v) {
      if (referenced[v]) continue;
      // Several candidates, so that an exact tie goes to the lower index
      // rather than to the tree's traversal order.
      const std::vector<Neighbour> nearest = tree.nearest(p[v], 4);
      std::size_t best = donors[nearest.front().index];
      for (const Neighbour& n : nearest)
        if (n.distance == nearest.front().distance) best = std::min(best, donors[n.index]);
      normals[v] = normals[best];
    }
  }
  mesh.vertices.normals = std::move(normals);
  return report;
}

}  // namespace icrkit
