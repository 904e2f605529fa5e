#pragma once
/// \file
/// Uncertainty-aware region growth: a vertex joins a region only if the
/// grasp holds for every contact normal within an angle theta of its
/// estimated normal and every contact point within a distance delta of its
/// estimated position (theta = K normal_sigma, delta = K position_sigma from
/// the vertex attributes, or fixed bounds).
///
/// Construction (docs/icr.md, "Conservative growth"). The truth is the
/// Coulomb friction cone: forces of magnitude up to f within a = atan(mu)
/// of the true normal n, the circular cone the linearised pyramid
/// approximates from inside. Let the true contact be (n, p) with
/// angle(n, n^) <= theta and |p - p^| <= delta, and Q the smallest rotation
/// taking n^ to n (angle <= theta).
/// 1. Every tested primitive force F^ (the pyramid's edges and normal force
///    at n^) lies in the cone at n^, so Q F^ lies in the true cone, and
///    |Q F^ - F^| <= f c with c = 2 sin(theta / 2). The soft finger's
///    torsion moment t n^ turns into t n, off by t c.
/// 2. The witness wrench w' = (Q F^, (p x Q F^ + t n) / lambda) is a wrench
///    the true contact can apply, and differs from the tested w^ by at most
///    Delta = sqrt(eF^2 + eT^2), eF = f c,
///    eT = (delta f + |p^ - o| f c + mu_T f c) / lambda (mu_T: soft finger;
///    o the torque reference).
/// 3. A vertex qualifies when, in every search zone of its finger, some
///    tested wrench lies at least Delta beyond every facet of the zone
///    (facet normals are unit, so n . w' >= n . w^ - Delta). Then every
///    zone holds a wrench the true contact can apply, and the ICR theorem
///    (the supports of the chosen wrenches dominate the TWS's in every
///    direction, whichever points of the contacts' wrench sets hold the
///    zones) makes any choice of one vertex per region, at any true normals
///    and positions within the bounds, a grasp whose GWS holds the TWS.
/// With theta = delta = 0 the test is the plain one, exactly.
/// Against a linearised pyramid at the true normal whose edges sit at an
/// azimuth unrelated to the estimate's, Q F^ may lie outside it by up to
/// f sin(a) (1 - cos(pi / L)); that model is not the physical one and is
/// not what the bound covers.

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/contact_model.hpp>
#include <icrkit/icr/wrench.hpp>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace icrkit::icr {

struct ConservativeGrowth {
  /// K: the region must tolerate K standard deviations of each vertex's
  /// `normal_sigma` (radians) and `position_sigma` (metres) attributes.
  /// 1 covers 63 % of a vertex's normal errors under the fit model (a 2-D
  /// Gaussian tilt), 2 covers 98 %.
  double sigmas = 1.0;
  /// Fixed bounds used instead of K x the attributes: for meshes without
  /// them (CAD meshes) or a known sensor accuracy. Radians and metres.
  std::optional<double> normal_angle;
  std::optional<double> position_offset;

  /// InputError (source "conservative growth") on a negative or non-finite
  /// value, or a normal angle above pi.
  void validate() const;
};

/// Per vertex of one mesh: the normal angle and position offset a region
/// must tolerate, read from the attributes as vertices are tested.
class UncertaintyBounds {
public:
  /// Keeps a reference to `mesh`. Throws InputError when the mesh lacks
  /// `normal_sigma` / `position_sigma` and no fixed bound replaces the
  /// missing one.
  UncertaintyBounds(const TriangleMesh& mesh, const ConservativeGrowth& growth);
  /// Radians, at most pi. These two throw InputError naming the vertex when
  /// its sigma is negative or not finite.
  double angle(std::size_t vertex) const;
  /// Metres.
  double offset(std::size_t vertex) const;

private:
  const Attribute* normal_sigma_ = nullptr;
  const Attribute* position_sigma_ = nullptr;
  double sigmas_ = 0.0;
  double fixed_angle_ = 0.0, fixed_offset_ = 0.0;
};

/// Delta of step 2 for a contact at `point` (estimated) with bounds `angle`
/// (radians) and `offset` (metres).
double wrenchUncertainty(const ContactModel& model, const WrenchFrame& frame, const Eigen::Vector3d& point, double angle,
                         double offset);

}  // namespace icrkit::icr
