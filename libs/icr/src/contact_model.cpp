#include <icrkit/core/error.hpp>
#include <icrkit/icr/contact_model.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace icrkit::icr {

void ContactModel::validate() const {
  auto fail = [](const std::string& detail) { throw InputError("contact model", "", detail); };
  if (!(force > 0) || !std::isfinite(force)) fail("the force magnitude must be positive, got " + std::to_string(force));
  if (type == ContactType::Frictionless) return;
  if (!(friction > 0) || !std::isfinite(friction))
    fail("the friction coefficient mu must be positive, got " + std::to_string(friction));
  if (cone_edges < 3) fail("the friction cone needs at least 3 edges, got " + std::to_string(cone_edges));
  if (type == ContactType::SoftFinger && (!(torsional_friction > 0) || !std::isfinite(torsional_friction)))
    fail("the torsional friction coefficient mu_T must be positive, got " + std::to_string(torsional_friction));
}

std::size_t ContactModel::wrenchesPerContact() const {
  switch (type) {
    case ContactType::Frictionless: return 1;
    case ContactType::Frictional: return static_cast<std::size_t>(cone_edges) + (include_normal ? 1 : 0);
    case ContactType::SoftFinger: return static_cast<std::size_t>(cone_edges) + (include_normal ? 1 : 0) + 2;
  }
  return 0;
}

const char* contactTypeName(ContactType type) {
  switch (type) {
    case ContactType::Frictionless: return "frictionless";
    case ContactType::Frictional: return "frictional";
    case ContactType::SoftFinger: return "soft";
  }
  return "unknown";
}

ContactType parseContactType(const std::string& name) {
  for (ContactType type : {ContactType::Frictional, ContactType::Frictionless, ContactType::SoftFinger})
    if (name == contactTypeName(type)) return type;
  throw InputError("contact model", "", "expected frictional, frictionless or soft, got '" + name + "'");
}

std::string contactModelJson(const ContactModel& model) {
  nlohmann::json out{{"type", contactTypeName(model.type)}, {"force_n", model.force}};
  if (model.type != ContactType::Frictionless) {
    out["mu"] = model.friction;
    out["edges"] = model.cone_edges;
    out["include_normal"] = model.include_normal;
    if (model.type == ContactType::SoftFinger) out["mu_t"] = model.torsional_friction;
  }
  return out.dump();
}

std::vector<LocalPrimitive> localPrimitives(const ContactModel& model) {
  model.validate();
  const double f = model.force;
  std::vector<LocalPrimitive> primitives;
  if (model.type == ContactType::Frictionless || model.include_normal)
    primitives.push_back({Eigen::Vector3d(0, 0, f), 0.0});
  if (model.type == ContactType::Frictionless) return primitives;
  const double half_angle = std::atan(model.friction);
  const int edges = model.cone_edges;
  for (int k = 0; k < edges; ++k) {
    const double t = -M_PI + 2.0 * M_PI * k / edges;
    primitives.push_back({Eigen::Vector3d(f * std::sin(half_angle) * std::cos(t), f * std::sin(half_angle) * std::sin(t),
                                          f * std::cos(half_angle)),
                          0.0});
  }
  if (model.type == ContactType::SoftFinger) {
    primitives.push_back({Eigen::Vector3d(0, 0, f), model.torsional_friction * f});
    primitives.push_back({Eigen::Vector3d(0, 0, f), -model.torsional_friction * f});
  }
  return primitives;
}

Eigen::Matrix3d rotationFromZ(const Eigen::Vector3d& n) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d axis = z.cross(n);
  const double s = axis.norm();
  const double c = n.z();
  if (s < 1e-12) {
    if (c > 0) return Eigen::Matrix3d::Identity();
    return Eigen::Vector3d(1, -1, -1).asDiagonal();
  }
  // Rodrigues' formula for the rotation by atan2(s, c) about axis / s.
  Eigen::Matrix3d k;
  k << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Eigen::Matrix3d::Identity() + k + k * k * ((1.0 - c) / (s * s));
}

}  // namespace icrkit::icr
