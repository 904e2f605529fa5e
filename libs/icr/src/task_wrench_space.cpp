#include <icrkit/core/error.hpp>
#include <icrkit/icr/task_wrench_space.hpp>

#include <cmath>
#include <string>

namespace icrkit::icr {

TaskWrenchSpace TaskWrenchSpace::ball(double radius) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("task wrench space", "", "the ball radius must be positive, got " + std::to_string(radius));
  TaskWrenchSpace tws;
  tws.radius_ = radius;
  tws.wrenches_.resize(6, 0);
  return tws;
}

TaskWrenchSpace TaskWrenchSpace::polytope(WrenchSet wrenches) {
  if (wrenches.cols() == 0) throw InputError("task wrench space", "", "no disturbance wrenches given");
  if (!wrenches.allFinite()) throw InputError("task wrench space", "", "a disturbance wrench is not finite");
  TaskWrenchSpace tws;
  tws.wrenches_ = std::move(wrenches);
  tws.radius_ = tws.wrenches_.colwise().norm().maxCoeff();
  return tws;
}

double TaskWrenchSpace::support(const Wrench& u) const {
  if (isBall()) return radius_;
  return (u.transpose() * wrenches_).maxCoeff();
}

void TaskWrenchSpace::requireInside(const GraspWrenchSpace& gws) const {
  for (std::size_t f = 0; f < gws.facetCount(); ++f) {
    const double reach = support(gws.normals.col(static_cast<Eigen::Index>(f)));
    const double distance = -gws.offsets[f];
    if (reach > distance)
      throw InputError("task wrench space", "GWS facet " + std::to_string(f),
                       "the task wrench space reaches " + std::to_string(reach) +
                           " beyond the origin, past the facet at distance " + std::to_string(distance) +
                           ": the TWS must lie inside the GWS (lower alpha or the TWS radius)");
  }
}

}  // namespace icrkit::icr
