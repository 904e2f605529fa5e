#pragma once
/// \file
/// The Task Wrench Space: the disturbances a grasp must resist.

#include <icrkit/icr/grasp_wrench_space.hpp>

namespace icrkit::icr {

class TaskWrenchSpace {
public:
  /// An origin-centred ball of the given radius (> 0).
  static TaskWrenchSpace ball(double radius);
  /// The convex hull of user-given disturbance wrenches (at least one column).
  static TaskWrenchSpace polytope(WrenchSet wrenches);

  bool isBall() const { return wrenches_.cols() == 0; }
  double radius() const { return radius_; }
  const WrenchSet& wrenches() const { return wrenches_; }

  /// Support function: the largest u . t over the TWS (u unit).
  double support(const Wrench& u) const;

  /// Throws InputError naming the first facet of `gws` the TWS pokes through.
  void requireInside(const GraspWrenchSpace& gws) const;

private:
  double radius_ = 0.0;
  WrenchSet wrenches_;
};

}  // namespace icrkit::icr
