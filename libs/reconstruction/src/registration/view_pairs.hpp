#pragma once
// Pairs of views: counted once whichever way round they were registered or
// matched (the joint refinement's guard compares two such counts), and the
// groups of views the accepted ones link.

#include <icrkit/core/disjoint_sets.hpp>
#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>

#include <algorithm>
#include <cstdint>
#include <cstddef>
#include <utility>
#include <vector>

namespace icrkit::reconstruction {

inline std::size_t countUnorderedPairs(std::vector<std::pair<std::size_t, std::size_t>> pairs) {
  for (auto& [a, b] : pairs)
    if (b < a) std::swap(a, b);
  std::sort(pairs.begin(), pairs.end());
  return static_cast<std::size_t>(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
}

/// The views the accepted pairs link, as components of `views` views.
inline DisjointSets linkedViews(const std::vector<PairRegistrationRecord>& pairs, std::size_t views) {
  DisjointSets components(views);
  for (const PairRegistrationRecord& pair : pairs)
    if (pair.accepted) components.unite(std::uint32_t(pair.from), std::uint32_t(pair.to));
  return components;
}

}  // namespace icrkit::reconstruction
