#include <icrkit/core/mesh_distance.hpp>
#include <icrkit/core/mesh_sampling.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace icrkit {

MeshDistanceStatistics meshDistance(const TriangleMesh& from, const TriangleMesh& to,
                                    const MeshDistanceParameters& params) {
  from.validate();
  to.validate();
  if (from.vertexCount() == 0) throw std::invalid_argument("meshDistance: the measured mesh has no vertices");
  if (to.faceCount() == 0) throw std::invalid_argument("meshDistance: the reference mesh has no faces");

  std::vector<Eigen::Vector3d> queries = from.vertices.positions;
  // A mesh whose faces have no area can still be measured at its vertices.
  const bool has_area = std::any_of(from.faces.begin(), from.faces.end(), [&](const Triangle& f) {
    const auto& p = from.vertices.positions;
    return (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).squaredNorm() > 0.0;
  });
  if (params.samples > 0 && has_area) {
    const PointCloud samples = samplePointsUniformly(from, params.samples, params.seed);
    queries.insert(queries.end(), samples.positions.begin(), samples.positions.end());
  }

  const RayCaster caster(to);
  const std::vector<ClosestPoint> closest = caster.closestPoints(queries);
  std::vector<double> distances(closest.size());
  for (std::size_t i = 0; i < closest.size(); ++i) distances[i] = closest[i].distance;

  // Sequential sums in query order: the same result whatever the thread count.
  MeshDistanceStatistics stats;
  stats.points = distances.size();
  double sum = 0.0, sum2 = 0.0;
  for (const double d : distances) {
    stats.max = std::max(stats.max, d);
    sum += d;
    sum2 += d * d;
  }
  const auto n = static_cast<double>(distances.size());
  stats.mean = sum / n;
  stats.rms = std::sqrt(sum2 / n);
  const std::size_t middle = distances.size() / 2;
  std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(middle), distances.end());
  stats.median = distances[middle];
  if (distances.size() % 2 == 0)
    stats.median = 0.5 * (stats.median + *std::max_element(distances.begin(),
                                                            distances.begin() + static_cast<std::ptrdiff_t>(middle)));
  return stats;
}

double hausdorffDistance(const TriangleMesh& a, const TriangleMesh& b, const MeshDistanceParameters& params) {
  return std::max(meshDistance(a, b, params).max, meshDistance(b, a, params).max);
}

}  // namespace icrkit
