#pragma once
/// \file
/// How surely a grasp holds where a robot puts its fingers: the robot aims
/// each finger at its region's recommended contact and misses by its
/// placement error, a 2-D Gaussian in the plane of the contact (sigma per
/// axis). A finger that lands inside its region keeps the ICR guarantee
/// whatever the other fingers do; so the probability that every finger
/// lands inside its region is a lower bound on the probability that the
/// grasp holds the task on the mesh, and the score.
///
/// It is estimated with a fixed set of offsets (drawn once from a fixed
/// seed, the same for every candidate so that candidates are compared on
/// the same draws), each landing point snapped to the nearest surface
/// vertex that faces the aim's way; per finger the fraction of offsets that
/// land inside its region, multiplied over the fingers.

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <vector>

namespace icrkit::planning {

struct PlacementParameters {
  /// The robot's fingertip placement error (metres): sigma of the Gaussian
  /// along each of the two tangent axes. 0: the finger lands where aimed.
  double placement_error_m = 0.003;
  /// Offsets per finger (>= 1).
  std::size_t samples = 128;

  /// InputError naming the field for a value out of range.
  void validate() const;
};

struct PlacementScore {
  double probability = 0.0;               ///< every finger inside its region (estimate)
  std::vector<double> finger_probability;  ///< per finger
  double min_depth_m = 0.0;               ///< the shallowest recommended contact's depth in its region
};

/// The surface vertices of one object and the fixed offsets, shared by
/// every candidate. Thread-safe after construction.
class PlacementScorer {
public:
  /// Keeps a reference to `object`.
  PlacementScorer(const icr::GraspableObject& object, const PlacementParameters& params);
  ~PlacementScorer();

  PlacementScore score(const icr::IcrResult& regions) const;

  /// The vertex a finger aimed at `aim` along `normal` (outward, unit) lands
  /// on after the tangent `offset` (metres): the nearest surface vertex
  /// whose normal faces the aim's side (any nearest one if none does among
  /// the closest few); -1 on a mesh without surface vertices.
  int landing(const Eigen::Vector3d& aim, const Eigen::Vector3d& normal, const Eigen::Vector2d& offset) const;

private:
  const icr::GraspableObject& object_;
  PlacementParameters params_;
  std::vector<Eigen::Vector3d> surface_;  // positions of the vertices faces use
  std::vector<int> surface_index_;        // their mesh indices
  std::unique_ptr<KdTree> tree_;
  std::vector<Eigen::Vector2d> offsets_;
};

/// Two unit vectors completing `normal` (unit) to a right-handed frame.
void tangentBasis(const Eigen::Vector3d& normal, Eigen::Vector3d& t1, Eigen::Vector3d& t2);

}  // namespace icrkit::planning
