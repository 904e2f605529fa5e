#pragma once
/// \file
/// Wrenches and the frame they are expressed in.

#include <icrkit/icr/contact_model.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace icrkit::icr {

using Wrench = Eigen::Matrix<double, 6, 1>;  ///< (force, torque / lambda)
using WrenchSet = Eigen::Matrix<double, 6, Eigen::Dynamic>;  ///< one wrench per column

/// Torques are taken about `reference_point` and divided by `lambda` so that
/// force and torque components are commensurate. CAD and reconstructed
/// meshes of one object should share one frame.
struct WrenchFrame {
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();  ///< metres
  double lambda = 1.0;                                          ///< characteristic length, metres
};

enum class TorqueReference { Origin, Centroid };

/// "origin", "centroid".
const char* torqueReferenceName(TorqueReference reference);
/// The inverse; InputError (source "torque reference") naming the choices.
TorqueReference parseTorqueReference(const std::string& name);

/// Reference point (frame origin or the points' centroid) and lambda = the
/// largest distance of a point from it. InputError for an empty set or a
/// zero lambda.
WrenchFrame makeWrenchFrame(const std::vector<Eigen::Vector3d>& points, TorqueReference reference = TorqueReference::Origin);

/// Turns contact positions and normals into wrenches for one contact model
/// and frame. The local primitives are computed once.
class ContactWrenches {
public:
  ContactWrenches(const ContactModel& model, const WrenchFrame& frame);

  std::size_t perContact() const { return primitives_.size(); }
  /// Writes perContact() wrenches of the contact at `point` with outward
  /// unit `normal` into columns [first, first + perContact()) of `out`.
  void compute(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, WrenchSet& out, Eigen::Index first) const;
  /// The wrenches of one contact as a 6 x perContact() matrix.
  WrenchSet compute(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) const;

  const WrenchFrame& frame() const { return frame_; }

private:
  std::vector<LocalPrimitive> primitives_;
  WrenchFrame frame_;
};

}  // namespace icrkit::icr
