#pragma once
// What every ICR entry point (single-point and patch contacts) does with a
// prototype grasp before growing regions, with the same messages: its
// checks, its task wrench space, and the phase timings.

#include <icrkit/icr/independent_contact_regions.hpp>

#include <chrono>
#include <vector>

namespace icrkit::icr::detail {

/// Throws InputError (source "grasp") on fewer than 2 contacts, an
/// out-of-range, unreferenced, excluded or repeated contact, and (source
/// "task wrench space") on alpha outside (0, 1] when alpha sizes the TWS.
void checkPrototype(const GraspableObject& object, const std::vector<int>& contacts, const IcrParameters& params);

/// The TWS the parameters ask for (polytope, absolute ball, or alpha x the
/// prototype's epsilon), checked to fit inside `gws` (InputError if not).
TaskWrenchSpace taskWrenchSpaceFor(const IcrParameters& params, const GraspWrenchSpace& gws);

using Clock = std::chrono::steady_clock;

}  // namespace icrkit::icr::detail
