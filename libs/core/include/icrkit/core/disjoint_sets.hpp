#pragma once
/// \file
/// Disjoint sets (union-find) over the indices 0..n-1, with path halving.
/// A union makes the smaller root the root of both, so the roots after a
/// given sequence of unions depend on nothing else.

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace icrkit {

class DisjointSets {
public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::uint32_t{0}); }

  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  /// Joins the sets of `a` and `b`; false when they were one already.
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (a > b) std::swap(a, b);
    parent_[b] = a;
    return true;
  }

private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace icrkit
