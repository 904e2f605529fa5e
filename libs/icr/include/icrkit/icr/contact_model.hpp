#pragma once
/// \file
/// Contact models: the primitive wrenches one finger contact can apply.
///
/// The convention is the one of the reference ICR library (see
/// docs/icr.md): force magnitude f; a frictional cone with half-angle
/// atan(mu) linearised by L edges at angles t_k = -pi + 2 pi k / L, plus the
/// pure normal force; the soft finger adds the normal force with torsional
/// moments +-mu_T f about the normal.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <string>
#include <vector>

namespace icrkit::icr {

enum class ContactType { Frictionless, Frictional, SoftFinger };

struct ContactModel {
  ContactType type = ContactType::Frictional;
  double friction = 0.8;            ///< Coulomb coefficient mu (dimensionless)
  int cone_edges = 8;               ///< L, edges of the linearised friction cone
  double torsional_friction = 0.5;  ///< mu_T of the soft finger; the moment is mu_T * f (N m per N)
  bool include_normal = true;       ///< also apply the pure normal force (frictional and soft finger)
  double force = 1.0;               ///< f, force magnitude (N)

  /// Throws InputError (source "contact model") on a parameter out of range.
  void validate() const;
  /// Number of primitive wrenches of one contact.
  std::size_t wrenchesPerContact() const;
};

/// "frictional", "frictionless", "soft": the names the command and the
/// Python package use.
const char* contactTypeName(ContactType type);
/// The inverse; InputError (source "contact model") naming the choices.
ContactType parseContactType(const std::string& name);
/// The model as the commands' summaries and run.json record it, compact JSON
/// with sorted keys: {"type", "force_n"} and, with friction, "mu", "edges",
/// "include_normal" ("mu_t" for the soft finger).
std::string contactModelJson(const ContactModel& model);

/// A primitive of the contact, in the contact frame (+z along the normal).
struct LocalPrimitive {
  Eigen::Vector3d force;
  double torsion = 0.0;  ///< moment about the normal (N m)
};

std::vector<LocalPrimitive> localPrimitives(const ContactModel& model);

/// The smallest rotation taking +z onto the unit vector n (identity for n = +z,
/// diag(1, -1, -1) for n = -z).
Eigen::Matrix3d rotationFromZ(const Eigen::Vector3d& n);

}  // namespace icrkit::icr
