#pragma once
// Nearest-target searches for source points that move a little between
// calls: the iterations of a point-to-plane ICP or of the joint refinement.
// Most sources of a pair of views find nothing within the pairing distance
// (they lie where the other view did not look), and the search tree spends
// most of its time proving that again in every iteration. Each source keeps
// a lower bound on its distance to the targets, taken where it was last
// searched; until it has moved far enough from there for a target to come
// within the pairing distance, it is not searched again.
//
// Exact: a call returns what a fresh search within `max_distance` returns
// (the bound only ever skips sources that search would find nothing for),
// so the registrations' results do not change, only their time.

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

class MissBounds {
public:
  MissBounds() = default;
  explicit MissBounds(std::size_t sources) : at_(sources, Eigen::Vector3f::Zero()), bound_(sources, 0.0f) {}

  std::size_t size() const { return bound_.size(); }

  /// Index of the nearest of `targets` strictly within `max_distance` of
  /// `query` (source `k`, placed), or -1. `search(query, radius)` is the
  /// tree's strict nearest-within search; it is asked with `reach` (>=
  /// `max_distance`), so that a miss bounds the source for longer.
  template <class Search>
  long nearestWithin(std::size_t k, const Eigen::Vector3d& query, double max_distance, double reach,
                     const std::vector<Eigen::Vector3d>& targets, const Search& search) {
    // Floats halve the memory (a joint refinement of 36 views keeps up to
    // 1,260 x 3,000 bounds). Their rounding, under 1.1e-7 of the largest
    // coordinate in the stored point and 6e-8 of the bound, is covered by a
    // slack that grows with both: the skip stays exact at any distance from
    // the frame's origin.
    const double moved = (query - at_[k].cast<double>()).norm();
    const double slack = 1e-9 + 2.5e-7 * (query.cwiseAbs().maxCoeff() + moved + double(bound_[k]));
    if (double(bound_[k]) - moved - slack >= max_distance) return -1;
    const double radius = reach > max_distance ? reach : max_distance;
    const long found = search(query, radius);
    double distance_sq = radius * radius;
    if (found >= 0) {
      // Summed as the tree sums it: the same verdict at the boundary.
      const Eigen::Vector3d& t = targets[static_cast<std::size_t>(found)];
      const double dx = query.x() - t.x(), dy = query.y() - t.y(), dz = query.z() - t.z();
      distance_sq = dx * dx + dy * dy + dz * dz;
    }
    at_[k] = query.cast<float>();
    bound_[k] = static_cast<float>(std::sqrt(distance_sq));
    return found >= 0 && distance_sq < max_distance * max_distance ? found : -1;
  }

private:
  std::vector<Eigen::Vector3f> at_;  // where each source was last searched
  std::vector<float> bound_;         // its distance to the targets there, at least
};

}  // namespace icrkit::reconstruction
