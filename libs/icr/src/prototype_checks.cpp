#include "prototype_checks.hpp"

#include <icrkit/core/error.hpp>

#include <string>

namespace icrkit::icr::detail {

void checkPrototypeContacts(const GraspableObject& object, const std::vector<int>& contacts) {
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
}

}  // namespace icrkit::icr::detail
