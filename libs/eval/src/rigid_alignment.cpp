#include <icrkit/eval/rigid_alignment.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace icrkit::eval {
namespace {

constexpr const char* kSource = "rigid alignment";

void validate(const AlignmentParameters& p) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(p.max_distance) || !positive(p.min_distance) || p.min_distance > p.max_distance)
    throw InputError(kSource, "distances", "expected 0 < min_distance <= max_distance (metres)");
  if (!positive(p.huber)) throw InputError(kSource, "huber", "expected a length > 0 (metres)");
  if (!positive(p.tolerance)) throw InputError(kSource, "tolerance", "expected a length > 0 (metres)");
  if (p.max_iterations < 1) throw InputError(kSource, "max_iterations", "expected at least 1");
}

struct Pairing {
  std::size_t pairs = 0;
  double rms = 0.0;
};

}  // namespace

void transformMesh(TriangleMesh& mesh, const Eigen::Isometry3d& transform) {
  for (auto& p : mesh.vertices.positions) p = transform * p;
  for (auto& n : mesh.vertices.normals) n = transform.linear() * n;
}

AlignmentResult alignToCad(const TriangleMesh& moving, const TriangleMesh& cad, const AlignmentParameters& params) {
  validate(params);
  if (moving.vertexCount() == 0) throw InputError(kSource, "moving mesh", "has no vertices");
  if (cad.faces.empty()) throw InputError(kSource, "CAD mesh", "has no faces");
  const RayCaster caster(cad);

  // An even stride keeps the sample spread over the whole surface; vertices
  // no face uses are not on it and are left out (a mesh without faces is a
  // point set: all its points count).
  const std::vector<Eigen::Vector3d> surface =
      moving.faces.empty() ? moving.vertices.positions : referencedPositions(moving);
  if (surface.empty()) throw InputError(kSource, "moving mesh", "has no vertex that a face uses");
  std::vector<Eigen::Vector3d> samples;
  const std::size_t n = surface.size();
  const std::size_t stride = params.max_samples == 0 ? 1 : std::max<std::size_t>(1, n / params.max_samples);
  for (std::size_t i = 0; i < n; i += stride) samples.push_back(surface[i]);
  double reach = 0.0;  // how far a rotation step can move a sample
  for (const Eigen::Vector3d& s : samples) reach = std::max(reach, s.norm());

  AlignmentResult result;
  const auto residualRms = [&](const Eigen::Isometry3d& t, double limit) {
    std::vector<Eigen::Vector3d> moved(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) moved[i] = t * samples[i];
    const auto closest = caster.closestPoints(moved, limit);
    Pairing pairing;
    double sum = 0.0;
    for (const ClosestPoint& c : closest)
      if (c.found) {
        sum += c.distance * c.distance;
        ++pairing.pairs;
      }
    pairing.rms = pairing.pairs ? std::sqrt(sum / static_cast<double>(pairing.pairs)) : 0.0;
    return pairing;
  };
  const Pairing before = residualRms(result.transform, params.max_distance);
  if (before.pairs < 6)
    throw InputError(kSource, "moving mesh",
                     "only " + std::to_string(before.pairs) + " vertices lie within " +
                         std::to_string(params.max_distance) + " m of the CAD surface; align it roughly first");
  result.rms_before_m = before.rms;

  double limit = params.max_distance;
  std::vector<Eigen::Vector3d> moved(samples.size());
  for (int iteration = 0; iteration < params.max_iterations; ++iteration) {
    for (std::size_t i = 0; i < samples.size(); ++i) moved[i] = result.transform * samples[i];
    const auto closest = caster.closestPoints(moved, limit);
    // Serial accumulation in sample order: the same bits whatever the threads.
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    std::size_t pairs = 0;
    std::vector<double> distances;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const ClosestPoint& c = closest[i];
      if (!c.found || c.face_normal.squaredNorm() == 0.0) continue;
      const Eigen::Vector3d& normal = c.face_normal;
      const double residual = normal.dot(moved[i] - c.point);
      const double weight = std::abs(residual) <= params.huber ? 1.0 : params.huber / std::abs(residual);
      Eigen::Matrix<double, 6, 1> jacobian;
      jacobian << moved[i].cross(normal), normal;  // d residual / d (rotation, translation)
      normal_matrix.noalias() += weight * jacobian * jacobian.transpose();
      rhs.noalias() -= weight * residual * jacobian;
      distances.push_back(c.distance);
      ++pairs;
    }
    result.pairs = pairs;
    if (pairs < 6) break;
    const Eigen::Matrix<double, 6, 1> step = normal_matrix.ldlt().solve(rhs);
    if (!step.allFinite()) break;
    const Eigen::Vector3d omega = step.head<3>();
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
    if (omega.norm() > 0.0) delta.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
    delta.translation() = step.tail<3>();
    result.transform = delta * result.transform;
    result.iterations = iteration + 1;

    // Shrink the pairing limit towards three times the typical distance.
    std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                     distances.end());
    limit = std::clamp(3.0 * distances[distances.size() / 2], params.min_distance, limit);
    if (step.tail<3>().norm() + omega.norm() * reach < params.tolerance) {
      result.converged = true;
      break;
    }
  }
  result.rms_after_m = residualRms(result.transform, params.max_distance).rms;
  return result;
}

}  // namespace icrkit::eval
