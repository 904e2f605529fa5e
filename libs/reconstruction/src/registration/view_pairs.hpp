#pragma once
// Pairs of views counted once whichever way round they were registered or
// matched (the joint refinement's guard compares two such counts).

#include <algorithm>
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

}  // namespace icrkit::reconstruction
