#include <icrkit/planning/contact_trust.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>

namespace icrkit::planning {
namespace {

void requireLength(const char* field, double value) {
  if (!(std::isfinite(value) && value >= 0.0))
    throw InputError(field, "", "expected a finite value >= 0, got " + std::to_string(value));
}

// Distance along mesh edges from the nearest boundary vertex, computed only
// up to `limit` (beyond it: infinity), since only "closer than" is asked.
std::vector<double> distanceFromRim(const TriangleMesh& mesh, const VertexAdjacency& adjacency, double limit) {
  const std::vector<std::uint8_t> boundary = boundaryVertices(mesh);
  std::vector<double> distance(mesh.vertexCount(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t v = 0; v < boundary.size(); ++v)
    if (boundary[v]) {
      distance[v] = 0.0;
      queue.emplace(0.0, static_cast<int>(v));
    }
  const auto& p = mesh.vertices.positions;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    const auto vs = static_cast<std::size_t>(v);
    if (d > distance[vs]) continue;
    for (const int* it = adjacency.begin(vs); it != adjacency.end(vs); ++it) {
      const auto u = static_cast<std::size_t>(*it);
      const double through = d + (p[u] - p[vs]).norm();
      if (through < distance[u] && through < limit) {
        distance[u] = through;
        queue.emplace(through, *it);
      }
    }
  }
  return distance;
}

}  // namespace

void ContactTrustParameters::validate() const {
  requireLength("ContactTrustParameters::rim_distance_m", rim_distance_m);
  requireLength("ContactTrustParameters::footprint_radius_m", footprint_radius_m);
  requireLength("ContactTrustParameters::max_normal_spread_rad", max_normal_spread_rad);
  if (max_normal_sigma_rad) requireLength("ContactTrustParameters::max_normal_sigma_rad", *max_normal_sigma_rad);
}

ContactTrust assessContactTrust(const TriangleMesh& mesh, const std::vector<std::uint8_t>& excluded,
                                const ContactTrustParameters& params) {
  params.validate();
  const std::size_t n = mesh.vertexCount();
  if (!excluded.empty() && excluded.size() != n)
    throw InputError("exclusion mask", "",
                     "expected " + std::to_string(n) + " flags, one per vertex, got " + std::to_string(excluded.size()));
  if (mesh.vertices.normals.size() != n) throw InputError("mesh", "", "contact trust needs one normal per vertex");

  const std::vector<std::uint8_t> referenced = referencedVertices(mesh);
  const VertexAdjacency adjacency = vertexAdjacency(mesh);
  const std::vector<double> rim = distanceFromRim(mesh, adjacency, params.rim_distance_m);
  const Attribute* sigma = params.max_normal_sigma_rad ? mesh.vertices.attributes.find("normal_sigma") : nullptr;

  // The largest angle between a vertex's normal and those of the surface
  // vertices under the fingertip centred on it.
  const auto& positions = mesh.vertices.positions;
  const auto& normals = mesh.vertices.normals;
  std::vector<std::uint8_t> spread_ok(n, 1);
  if (params.footprint_radius_m > 0.0) {
    const KdTree tree(positions);
    const double min_cos = std::cos(params.max_normal_spread_rad);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<std::size_t> near;
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        if (!referenced[v]) continue;
        tree.indicesWithinRadiusInTreeOrder(positions[v], params.footprint_radius_m, near);
        for (std::size_t u : near)
          if (referenced[u] && normals[u].dot(normals[v]) < min_cos) {
            spread_ok[v] = 0;
            break;
          }
      }
    });
  }

  ContactTrust trust;
  trust.untrusted.assign(n, 1);
  ContactTrustReport& r = trust.report;
  for (std::size_t v = 0; v < n; ++v) {
    if (!referenced[v]) continue;
    ++r.vertices;
    if (!excluded.empty() && excluded[v]) {
      ++r.excluded;
    } else if (rim[v] < params.rim_distance_m || (params.rim_distance_m == 0.0 && rim[v] == 0.0)) {
      ++r.near_rim;
    } else if (!spread_ok[v]) {
      ++r.normal_spread;
    } else if (sigma && !(sigma->values[v] <= *params.max_normal_sigma_rad)) {
      ++r.normal_sigma;
    } else {
      trust.untrusted[v] = 0;
      ++r.trusted;
    }
  }
  return trust;
}

}  // namespace icrkit::planning
