#include <icrkit/icr/contact_snapping.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <string>

namespace icrkit::icr {

SnappedContacts snapToFaceVertices(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  const std::vector<std::uint8_t> referenced = referencedVertices(mesh);
  std::vector<int> surface;
  std::vector<Eigen::Vector3d> positions;
  for (std::size_t v = 0; v < referenced.size(); ++v)
    if (referenced[v]) {
      surface.push_back(static_cast<int>(v));
      positions.push_back(mesh.vertices.positions[v]);
    }
  if (surface.empty()) throw InputError("mesh", "", "has no vertex of a face to snap contact points to");
  const KdTree tree(positions);
  SnappedContacts snapped;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw InputError("contact points", "point " + std::to_string(i + 1), "expected finite x, y, z");
    const Neighbour nearest = tree.nearest(points[i], 1).front();
    snapped.vertices.push_back(surface[nearest.index]);
    snapped.distances_m.push_back(nearest.distance);
  }
  return snapped;
}

}  // namespace icrkit::icr
