#include <icrkit/icr/grasp_transfer.hpp>

#include <icrkit/core/error.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <tuple>

namespace icrkit::icr {
namespace {

double mappingRadius(const TriangleMesh& target, const NormalLineMappingParameters& params) {
  if (!std::isfinite(params.search_radius) || params.search_radius < 0.0)
    throw InputError("normal-line mapping", "search radius",
                     "expected a finite radius >= 0 (0 = automatic), got " + std::to_string(params.search_radius));
  if (target.vertexCount() == 0) throw InputError("normal-line mapping", "target mesh", "the target has no vertices");
  if (params.search_radius > 0.0) return params.search_radius;
  // Ten spacings reach well past the surface noise of a reconstruction but
  // stay far short of the object's other side on anything graspable.
  const double radius = 10.0 * nearestNeighbourSpacing(target.vertices.positions).median;
  if (!(radius > 0.0))
    throw InputError("normal-line mapping", "target mesh",
                     "the median vertex spacing is 0, so no automatic search radius exists; give one");
  return radius;
}

}  // namespace

NormalLineMapping::NormalLineMapping(const TriangleMesh& target, const NormalLineMappingParameters& params)
    : target_(&target), tree_(target.vertices.positions), radius_(mappingRadius(target, params)) {}

int NormalLineMapping::map(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  const double length = n.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    throw InputError("normal-line mapping", "normal", "expected a finite non-zero normal");
  if (!p.allFinite()) throw InputError("normal-line mapping", "point", "expected finite coordinates");
  const Eigen::Vector3d direction = n / length;
  const auto& positions = target_->vertices.positions;

  // Lexicographic (distance to the line, distance to p, index): a total
  // order, so the answer never depends on the kd-tree's traversal.
  int best = -1;
  std::tuple<double, double, std::size_t> best_key;
  for (const Neighbour& candidate : tree_.withinRadius(p, radius_)) {
    const double to_line = direction.cross(p - positions[candidate.index]).norm();
    const std::tuple<double, double, std::size_t> key(to_line, candidate.distance, candidate.index);
    if (best < 0 || key < best_key) {
      best = static_cast<int>(candidate.index);
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
