#include <icrkit/core/mesh_sampling.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace icrkit {
namespace {

// SplitMix64 finaliser: a bijection on 64-bit words that scrambles every bit.
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Sample i draws from a SplitMix64 stream keyed by (seed, i) alone, so the
// samples can be made in any order on any number of threads and still be
// the same for a seed.
class SampleRandom {
public:
  SampleRandom(std::uint64_t seed, std::uint64_t sample) : state_(mix64(mix64(seed) ^ sample)) {}

  // Uniform in [0, 1) on a 2^-53 grid; spelled out (rather than a standard
  // distribution) so results agree across standard libraries.
  double uniform() {
    state_ += 0x9E3779B97F4A7C15ULL;
    return static_cast<double>(mix64(state_) >> 11) * 0x1.0p-53;
  }

private:
  std::uint64_t state_;
};

}  // namespace

PointCloud samplePointsUniformly(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed) {
  mesh.validate();
  PointCloud cloud;
  if (count == 0) return cloud;

  // Running area sums, in face order: picking a face is then a binary
  // search for a uniform value in [0, total).
  const std::vector<double> areas = faceAreas(mesh);
  std::vector<double> cumulative(areas.size());
  std::partial_sum(areas.begin(), areas.end(), cumulative.begin());
  const double total = cumulative.empty() ? 0.0 : cumulative.back();
  if (!(total > 0.0))
    throw std::invalid_argument("samplePointsUniformly: the mesh has no area to sample (" +
                                std::to_string(mesh.faceCount()) + " faces)");
  // A draw that rounds up to `total` must still land on a face with area.
  const auto last_with_area = static_cast<std::size_t>(
      std::find_if(areas.rbegin(), areas.rend(), [](double a) { return a > 0.0; }).base() - areas.begin() - 1);

  const auto& positions = mesh.vertices.positions;
  const auto& vertex_normals = mesh.vertices.normals;
  const bool blend_normals = mesh.vertices.hasNormals();
  cloud.positions.resize(count);
  cloud.normals.resize(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      SampleRandom random(seed, i);
      const double pick = random.uniform() * total;
      // upper_bound skips faces of zero area: their running sum equals the previous one.
      auto face_index = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) -
                                                 cumulative.begin());
      face_index = std::min(face_index, last_with_area);
      const Triangle& f = mesh.faces[face_index];
      const auto ia = static_cast<std::size_t>(f[0]), ib = static_cast<std::size_t>(f[1]),
                 ic = static_cast<std::size_t>(f[2]);

      // Without the square root the points would crowd towards corner a.
      const double s = std::sqrt(random.uniform());
      const double r = random.uniform();
      const double wa = 1.0 - s, wb = s * (1.0 - r), wc = s * r;
      // Offsets from a rather than a weighted sum of three corners: a
      // coordinate the corners share comes out exactly (flat sides stay flat).
      cloud.positions[i] = positions[ia] + wb * (positions[ib] - positions[ia]) + wc * (positions[ic] - positions[ia]);

      const Eigen::Vector3d face_normal =
          (positions[ib] - positions[ia]).cross(positions[ic] - positions[ia]).normalized();
      Eigen::Vector3d normal = face_normal;
      if (blend_normals) {
        const Eigen::Vector3d blend = wa * vertex_normals[ia] + wb * vertex_normals[ib] + wc * vertex_normals[ic];
        const double length = blend.norm();
        if (length > 0.0) normal = blend / length;
      }
      cloud.normals[i] = normal;
    }
  });
  return cloud;
}

PointCloud samplePointsPoissonDisk(const TriangleMesh& mesh, double min_distance, std::uint64_t seed,
                                   double oversampling) {
  if (!(min_distance > 0.0) || !std::isfinite(min_distance))
    throw std::invalid_argument("samplePointsPoissonDisk: the minimum distance must be positive");
  if (!(oversampling >= 1.0)) throw std::invalid_argument("samplePointsPoissonDisk: oversampling must be >= 1");
  mesh.validate();
  const std::vector<double> areas = faceAreas(mesh);
  const double total = std::accumulate(areas.begin(), areas.end(), 0.0);
  // Densest packing: one disk of radius d/2 per sqrt(3)/2 d^2 of surface.
  const double capacity = total / (0.8660254037844386 * min_distance * min_distance);
  const auto candidates = static_cast<std::size_t>(std::ceil(oversampling * capacity)) + 1;
  const PointCloud pool = samplePointsUniformly(mesh, candidates, seed);

  // Cells of edge d: a point's rivals are in its own and the 26 cells around.
  const double inv = 1.0 / min_distance;
  const auto key = [&](const Eigen::Vector3d& p, int dx, int dy, int dz) {
    const auto cx = static_cast<std::int64_t>(std::floor(p.x() * inv)) + dx;
    const auto cy = static_cast<std::int64_t>(std::floor(p.y() * inv)) + dy;
    const auto cz = static_cast<std::int64_t>(std::floor(p.z() * inv)) + dz;
    return static_cast<std::uint64_t>((cx * 73856093) ^ (cy * 19349663) ^ (cz * 83492791));
  };
  std::unordered_multimap<std::uint64_t, std::size_t> grid;
  grid.reserve(static_cast<std::size_t>(capacity) + 1);
  const double d2 = min_distance * min_distance;
  PointCloud cloud;
  for (std::size_t i = 0; i < pool.size(); ++i) {
    const Eigen::Vector3d& p = pool.positions[i];
    bool free = true;
    for (int dx = -1; dx <= 1 && free; ++dx)
      for (int dy = -1; dy <= 1 && free; ++dy)
        for (int dz = -1; dz <= 1 && free; ++dz) {
          const auto range = grid.equal_range(key(p, dx, dy, dz));
          for (auto it = range.first; it != range.second; ++it)
            if ((cloud.positions[it->second] - p).squaredNorm() < d2) {
              free = false;
              break;
            }
        }
    if (!free) continue;
    grid.emplace(key(p, 0, 0, 0), cloud.positions.size());
    cloud.positions.push_back(p);
    cloud.normals.push_back(pool.normals[i]);
  }
  return cloud;
}

}  // namespace icrkit
