#include "prototype_checks.hpp"

#include <icrkit/core/error.hpp>

#include <cmath>
#include <string>

namespace icrkit::icr::detail {

void checkPrototype(const GraspableObject& object, const std::vector<int>& contacts, const IcrParameters& params) {
  auto fail = [](const std::string& detail) { throw InputError("grasp", "", detail); };
  if (contacts.size() < 2) fail("a grasp needs at least 2 contacts, got " + std::to_string(contacts.size()));
  const long n = static_cast<long>(object.vertexCount());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const int c = contacts[i];
    if (c < 0 || c >= n)
      fail("contact " + std::to_string(i) + " is vertex " + std::to_string(c) + ", expected 0.." + std::to_string(n - 1));
    if (!object.referenced(static_cast<std::size_t>(c)))
      fail("contact " + std::to_string(i) + " (vertex " + std::to_string(c) +
           ") is used by no face, so it is not on the surface; choose a vertex of a face");
    if (object.excluded(static_cast<std::size_t>(c)))
      fail("contact " + std::to_string(i) + " (vertex " + std::to_string(c) + ") is excluded by preselection");
    for (std::size_t j = 0; j < i; ++j)
      if (contacts[j] == c) fail("vertex " + std::to_string(c) + " is used by contacts " + std::to_string(j) + " and " + std::to_string(i));
  }
  if (params.tws_radius && !(std::isfinite(*params.tws_radius) && *params.tws_radius >= 0))
    throw InputError("IcrParameters::tws_radius", "",
                     "expected a finite radius >= 0, got " + std::to_string(*params.tws_radius));
  if (!params.tws_radius && !params.tws_wrenches && !(params.alpha > 0 && params.alpha <= 1))
    throw InputError("task wrench space", "", "alpha must be in (0, 1], got " + std::to_string(params.alpha));
}

TaskWrenchSpace taskWrenchSpaceFor(const IcrParameters& params, const GraspWrenchSpace& gws) {
  const TaskWrenchSpace tws = params.tws_wrenches ? TaskWrenchSpace::polytope(*params.tws_wrenches)
                              : params.tws_radius ? TaskWrenchSpace::ball(*params.tws_radius)
                                                  : TaskWrenchSpace::ball(params.alpha * gws.epsilon);
  tws.requireInside(gws);
  return tws;
}

}  // namespace icrkit::icr::detail
