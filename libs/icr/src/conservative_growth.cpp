#include <icrkit/core/error.hpp>
#include <icrkit/icr/conservative_growth.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace icrkit::icr {
namespace {

// The shared attribute names of the design card (written by the ndt library).
constexpr const char* kNormalSigma = "normal_sigma";
constexpr const char* kPositionSigma = "position_sigma";

double checkedSigma(const Attribute& attribute, std::size_t vertex) {
  const double sigma = attribute.values[vertex];
  if (!(sigma >= 0) || !std::isfinite(sigma))
    throw InputError("mesh", "vertex " + std::to_string(vertex),
                     "attribute " + attribute.name + " is " + std::to_string(sigma) + ", expected a finite value >= 0");
  return sigma;
}

}  // namespace

void ConservativeGrowth::validate() const {
  auto fail = [](const std::string& detail) { throw InputError("conservative growth", "", detail); };
  if (!(sigmas >= 0) || !std::isfinite(sigmas)) fail("K (sigmas) must be >= 0, got " + std::to_string(sigmas));
  if (normal_angle && (!(*normal_angle >= 0) || !(*normal_angle <= M_PI)))
    fail("the normal angle must be in [0, pi] radians, got " + std::to_string(*normal_angle));
  if (position_offset && (!(*position_offset >= 0) || !std::isfinite(*position_offset)))
    fail("the position offset must be >= 0 metres, got " + std::to_string(*position_offset));
}

UncertaintyBounds::UncertaintyBounds(const TriangleMesh& mesh, const ConservativeGrowth& growth)
    : sigmas_(growth.sigmas) {
  growth.validate();
  if (growth.normal_angle)
    fixed_angle_ = *growth.normal_angle;
  else
    normal_sigma_ = mesh.vertices.attributes.find(kNormalSigma);
  if (growth.position_offset)
    fixed_offset_ = *growth.position_offset;
  else
    position_sigma_ = mesh.vertices.attributes.find(kPositionSigma);
  std::string missing;
  if (!growth.normal_angle && !normal_sigma_) missing = kNormalSigma;
  if (!growth.position_offset && !position_sigma_) missing += std::string(missing.empty() ? "" : " and ") + kPositionSigma;
  if (!missing.empty())
    throw InputError("mesh", "",
                     "conservative growth needs the vertex attribute " + missing +
                         " (written by icrkit smooth, reconstruct, and mesh when it estimates normals); for a mesh "
                         "without it give a fixed normal angle and position offset");
}

double UncertaintyBounds::angle(std::size_t vertex) const {
  // A normal off by more than pi is not off by more than pi.
  return normal_sigma_ ? std::min(M_PI, sigmas_ * checkedSigma(*normal_sigma_, vertex)) : fixed_angle_;
}

double UncertaintyBounds::offset(std::size_t vertex) const {
  return position_sigma_ ? sigmas_ * checkedSigma(*position_sigma_, vertex) : fixed_offset_;
}

double wrenchUncertainty(const ContactModel& model, const WrenchFrame& frame, const Eigen::Vector3d& point, double angle,
                         double offset) {
  const double f = model.force;
  const double chord = 2.0 * std::sin(std::min(angle, M_PI) / 2.0);
  const double force_error = f * chord;
  const double arm = (point - frame.reference_point).norm();
  double torque_error = offset * f + arm * force_error;
  if (model.type == ContactType::SoftFinger) torque_error += model.torsional_friction * f * chord;
  torque_error /= frame.lambda;
  return std::sqrt(force_error * force_error + torque_error * torque_error);
}

}  // namespace icrkit::icr
