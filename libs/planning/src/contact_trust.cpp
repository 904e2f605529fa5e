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
#include <optional>
#include <queue>
#include <string>
#include <utility>

namespace icrkit::planning {
namespace {

void requireLength(const char* field, double value) {
  if (!(std::isfinite(value) && value >= 0.0))
    throw InputError(field, "", "expected a finite value >= 0, got " + std::to_string(value));
}

// Per vertex: 1 where the attribute `name` is below `fraction` of its median
// over the surface vertices; all 0 without the attribute or the fraction.
std::vector<std::uint8_t> belowFractionOfMedian(const TriangleMesh& mesh, const std::vector<std::uint8_t>& referenced,
                                                const char* name, const std::optional<double>& fraction) {
  const std::size_t n = mesh.vertexCount();
  std::vector<std::uint8_t> below(n, 0);
  const Attribute* attribute = fraction ? mesh.vertices.attributes.find(name) : nullptr;
  if (!attribute) return below;
  std::vector<double> values;
  for (std::size_t v = 0; v < n; ++v)
    if (referenced[v]) values.push_back(attribute->values[v]);
  if (values.empty()) return below;
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  const double bound = *fraction * *mid;
  for (std::size_t v = 0; v < n; ++v)
    if (referenced[v] && !(attribute->values[v] >= bound)) below[v] = 1;
  return below;
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
  requireLength("ContactTrustParameters::max_spread_fraction", max_spread_fraction);
  if (max_spread_fraction >= 1.0)
    throw InputError("ContactTrustParameters::max_spread_fraction", "",
                     "expected a fraction in [0, 1), got " + std::to_string(max_spread_fraction));
  if (max_normal_sigma_rad) requireLength("ContactTrustParameters::max_normal_sigma_rad", *max_normal_sigma_rad);
  if (min_relative_support) requireLength("ContactTrustParameters::min_relative_support", *min_relative_support);
  if (min_relative_flatness) requireLength("ContactTrustParameters::min_relative_flatness", *min_relative_flatness);
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
  // Thinly supported vertices (cardinality) and rounded features (flatness):
  // below a fraction of the attribute's median over the surface, a
  // scale-free rule (the values depend on the sensor, the views and the NDT
  // window).
  const std::vector<std::uint8_t> weak = belowFractionOfMedian(mesh, referenced, "cardinality", params.min_relative_support);
  const bool any_weak = std::find(weak.begin(), weak.end(), 1) != weak.end();
  const std::vector<std::uint8_t> rounded =
      belowFractionOfMedian(mesh, referenced, "flatness", params.min_relative_flatness);

  std::vector<std::uint8_t> spread_ok(n, 1), support_ok(n, 1);
  for (std::size_t v = 0; v < n; ++v) support_ok[v] = weak[v] ? 0 : 1;
  if (params.footprint_radius_m > 0.0) {
    const KdTree tree(positions);
    const double min_cos = std::cos(params.max_normal_spread_rad);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<std::size_t> near;
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        if (!referenced[v]) continue;
        tree.indicesWithinRadiusInTreeOrder(positions[v], params.footprint_radius_m, near);
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        std::size_t count = 0;
        for (std::size_t u : near) {
          if (!referenced[u]) continue;
          if (any_weak && weak[u]) support_ok[v] = 0;
          mean += normals[u];
          ++count;
        }
        const double length = mean.norm();
        if (!(length > 0.0)) {
          spread_ok[v] = 0;
          continue;
        }
        mean /= length;
        if (normals[v].dot(mean) < min_cos) {
          spread_ok[v] = 0;
          continue;
        }
        std::size_t off = 0;
        for (std::size_t u : near)
          if (referenced[u] && normals[u].dot(mean) < min_cos) ++off;
        if (static_cast<double>(off) > params.max_spread_fraction * static_cast<double>(count)) spread_ok[v] = 0;
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
    } else if (!support_ok[v]) {
      ++r.weak_support;
    } else if (rounded[v]) {
      ++r.low_flatness;
    } else {
      trust.untrusted[v] = 0;
      ++r.trusted;
    }
  }
  return trust;
}

}  // namespace icrkit::planning
