#include <icrkit/icr/grasp_transfer.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>

namespace icrkit::icr {
namespace {

// The target vertices that may be chosen, with their indices: those some
// face uses, or every point of a target without faces.
std::vector<int> competingVertices(const TriangleMesh& target) {
  std::vector<int> indices;
  const std::vector<std::uint8_t> referenced = referencedVertices(target);
  for (std::size_t v = 0; v < target.vertexCount(); ++v)
    if (target.faces.empty() || referenced[v]) indices.push_back(static_cast<int>(v));
  return indices;
}

std::vector<Eigen::Vector3d> positionsOf(const TriangleMesh& target, const std::vector<int>& indices) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(indices.size());
  for (const int v : indices) points.push_back(target.vertices.positions[static_cast<std::size_t>(v)]);
  return points;
}

double mappingRadius(const std::vector<Eigen::Vector3d>& points, const NormalLineMappingParameters& params) {
  if (params.search_radius && !(std::isfinite(*params.search_radius) && *params.search_radius > 0.0))
    throw InputError(
        "NormalLineMappingParameters::search_radius", "",
        "expected a finite radius > 0 (or unset: automatic), got " + std::to_string(*params.search_radius));
  if (points.empty()) throw InputError("normal-line mapping", "target mesh", "the target has no vertices");
  if (params.search_radius) return *params.search_radius;
  // Ten spacings reach well past the surface noise of a reconstruction but
  // stay far short of the object's other side on anything graspable.
  const double radius = 10.0 * nearestNeighbourSpacing(points).median;
  if (!(radius > 0.0))
    throw InputError("normal-line mapping", "target mesh",
                     "the median vertex spacing is 0, so no automatic search radius exists; give one");
  return radius;
}

}  // namespace

NormalLineMapping::NormalLineMapping(const TriangleMesh& target, const NormalLineMappingParameters& params)
    : target_(&target),
      index_(competingVertices(target)),
      points_(positionsOf(target, index_)),
      tree_(points_),
      radius_(mappingRadius(points_, params)) {}

int NormalLineMapping::map(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  const double length = n.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    throw InputError("normal-line mapping", "normal", "expected a finite non-zero normal");
  if (!p.allFinite()) throw InputError("normal-line mapping", "point", "expected finite coordinates");
  const Eigen::Vector3d direction = n / length;

  // Lexicographic (distance to the line, distance to p, index): a total
  // order, so the answer never depends on the kd-tree's traversal. The
  // competing vertices keep the target's order, so comparing their
  // positions in points_ compares target indices too.
  int best = -1;
  std::tuple<double, double, std::size_t> best_key;
  for (const Neighbour& candidate : tree_.withinRadius(p, radius_)) {
    const double to_line = direction.cross(p - points_[candidate.index]).norm();
    const std::tuple<double, double, std::size_t> key(to_line, candidate.distance, candidate.index);
    if (best < 0 || key < best_key) {
      best = index_[candidate.index];
      best_key = key;
    }
  }
  return best;
}

std::vector<int> transferGrasp(const TriangleMesh& source, const std::vector<int>& contacts, const TriangleMesh& target,
                               const NormalLineMappingParameters& params) {
  if (source.vertices.normals.size() != source.vertexCount())
    throw InputError("grasp transfer", "source mesh", "the source needs one normal per vertex");
  const NormalLineMapping mapping(target, params);
  const std::vector<std::uint8_t> referenced = referencedVertices(source);
  std::vector<int> mapped;
  mapped.reserve(contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const int vertex = contacts[i];
    const std::string location = "contact " + std::to_string(i) + " (vertex " + std::to_string(vertex) + ")";
    if (vertex < 0 || static_cast<std::size_t>(vertex) >= source.vertexCount())
      throw InputError("grasp transfer", location,
                       "vertex index out of range for a source of " + std::to_string(source.vertexCount()) +
                           " vertices");
    const auto v = static_cast<std::size_t>(vertex);
    if (!source.faces.empty() && !referenced[v])
      throw InputError("grasp transfer", location, "the vertex is used by no face of the source, so it is no contact");
    const int image = mapping.map(source.vertices.positions[v], source.vertices.normals[v]);
    if (image < 0)
      throw InputError("grasp transfer", location,
                       "no target vertex within the search radius of " + std::to_string(mapping.searchRadius()) +
                           " m");
    mapped.push_back(image);
  }
  return mapped;
}

}  // namespace icrkit::icr
