#include <icrkit/core/error.hpp>
#include <icrkit/icr/wrench.hpp>

#include <cmath>

namespace icrkit::icr {

const char* torqueReferenceName(TorqueReference reference) {
  return reference == TorqueReference::Centroid ? "centroid" : "origin";
}

TorqueReference parseTorqueReference(const std::string& name) {
  if (name == "origin") return TorqueReference::Origin;
  if (name == "centroid") return TorqueReference::Centroid;
  throw InputError("torque reference", "", "expected origin or centroid, got '" + name + "'");
}

WrenchFrame makeWrenchFrame(const std::vector<Eigen::Vector3d>& points, TorqueReference reference) {
  if (points.empty()) throw InputError("wrench frame", "", "no points to derive the torque reference and lambda from");
  WrenchFrame frame;
  if (reference == TorqueReference::Centroid) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) sum += p;
    frame.reference_point = sum / static_cast<double>(points.size());
  }
  double largest = 0.0;
  for (const Eigen::Vector3d& p : points) largest = std::max(largest, (p - frame.reference_point).norm());
  if (!(largest > 0))
    throw InputError("wrench frame", "", "every point coincides with the torque reference; lambda would be 0");
  frame.lambda = largest;
  return frame;
}

ContactWrenches::ContactWrenches(const ContactModel& model, const WrenchFrame& frame)
    : primitives_(localPrimitives(model)), frame_(frame) {
  if (!(frame.lambda > 0) || !std::isfinite(frame.lambda))
    throw InputError("wrench frame", "", "lambda must be positive, got " + std::to_string(frame.lambda));
}

void ContactWrenches::compute(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, WrenchSet& out,
                              Eigen::Index first) const {
  // Stored normals are unit only to a few digits; the rotation needs exactly unit.
  const Eigen::Vector3d unit = normal.normalized();
  const Eigen::Matrix3d rotation = rotationFromZ(unit);
  const Eigen::Vector3d arm = point - frame_.reference_point;
  const double inverse_lambda = 1.0 / frame_.lambda;
  for (std::size_t k = 0; k < primitives_.size(); ++k) {
    const Eigen::Vector3d force = rotation * primitives_[k].force;
    const Eigen::Vector3d torque = arm.cross(force) + primitives_[k].torsion * unit;
    auto column = out.col(first + static_cast<Eigen::Index>(k));
    column.head<3>() = force;
    column.tail<3>() = torque * inverse_lambda;
  }
}

WrenchSet ContactWrenches::compute(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) const {
  WrenchSet out(6, static_cast<Eigen::Index>(primitives_.size()));
  compute(point, normal, out, 0);
  return out;
}

}  // namespace icrkit::icr
