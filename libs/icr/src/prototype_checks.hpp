#pragma once
// The checks every ICR entry point makes on a prototype grasp, with the same
// messages (single-point and patch contacts alike).

#include <icrkit/icr/graspable_object.hpp>

#include <vector>

namespace icrkit::icr::detail {

/// Throws InputError (source "grasp") on fewer than 2 contacts, an
/// out-of-range, unreferenced, excluded or repeated contact.
void checkPrototypeContacts(const GraspableObject& object, const std::vector<int>& contacts);

}  // namespace icrkit::icr::detail
