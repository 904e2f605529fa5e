#pragma once
// Nearest-target searches for source points that move a little between
// calls: the iterations of a point-to-plane ICP or of the joint refinement.
//
// Misses: most sources of a pair of views find nothing within the pairing
// distance (they lie where the other view did not look), and a search tree
// spends most of its time proving that again in every iteration. Each source
// keeps a lower bound on its distance to the targets, taken where it was
// last searched; until it has moved far enough from there for a target to
// come within the pairing distance, it is not searched again. Blocks of
// consecutive sources keep such a bound too, with the placement it holds
// at, so a block far from the targets is passed over with one test.
//
// Hits: a source that found a target within the pairing distance keeps the
// targets around it, out to its nearest one's distance plus twice an
// allowance of motion. While it stays within the allowance of where it was
// searched, its nearest target is among those few, and a scan of them
// replaces the tree (on dense views: a dozen targets against a descent of
// the tree and its backtracking).
//
// Exact: a call returns what a fresh search within the pairing distance
// returns (the nearest target, the lowest index among equally near ones),
// so the registrations' results do not change, only their time.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace icrkit::reconstruction {

/// The search a NearestTracker asks, e.g. icrkit::KdTree:
/// `long nearestWithin(query, radius)` (strictly within, -1 for none) and
/// `void indicesWithinRadiusInTreeOrder(query, radius, out)`.
template <class Tree>
class NearestTracker {
public:
  struct Parameters {
    /// Sources are searched out to `reach` times the pairing distance, so
    /// that a miss is not searched again while it moves by the difference.
    double reach = 2.0;
    /// A hit keeps its surroundings while it moves less than this fraction
    /// of the pairing distance.
    double allowance = 0.25;
    /// Consecutive sources sharing one bound.
    std::size_t block_size = 32;
  };

  NearestTracker() = default;
  /// `sources` in their own frame, placed as a whole by each call.
  NearestTracker(const std::vector<Eigen::Vector3d>& sources, const Parameters& params)
      : params_(params), at_(sources.size(), Eigen::Vector3f::Zero()), bound_(sources.size(), 0.0f) {
    params_.block_size = std::max<std::size_t>(params_.block_size, 1);
    for (std::size_t begin = 0; begin < sources.size(); begin += params_.block_size) {
      const std::size_t end = std::min(sources.size(), begin + params_.block_size);
      Block b;
      for (std::size_t k = begin; k < end; ++k) b.centre += sources[k];
      b.centre /= double(end - begin);
      for (std::size_t k = begin; k < end; ++k) b.radius = std::max(b.radius, (sources[k] - b.centre).norm());
      blocks_.push_back(b);
    }
  }

  std::size_t size() const { return bound_.size(); }

  /// For every source `k` of the constructor's `sources` placed by
  /// `placement` (query = placement * sources[k]) with a target of `tree`
  /// (over `targets`) strictly within `max_distance`, in ascending k:
  /// visit(k, query, index of the nearest target). `sources`, `targets` and
  /// `tree` are the same in every call.
  template <class Visit>
  void forEachNearest(const std::vector<Eigen::Vector3d>& sources, const Eigen::Isometry3d& placement,
                      double max_distance, const std::vector<Eigen::Vector3d>& targets, const Tree& tree,
                      const Visit& visit) {
    if (!(max_distance > 0)) return;  // nothing is within; also rejects NaN
    // Stored first, so that the blocks never name a placement that is not
    // there (`visit` may throw); dropped below when no block used it.
    const auto placement_index = static_cast<std::uint32_t>(placements_.size());
    placements_.push_back(placement);
    bool placement_used = false;
    const double reach = std::max(params_.reach, 1.0) * max_distance;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      Block& block = blocks_[b];
      if (block.placed && block.lower - blockMove(block, placement) >= max_distance) continue;
      block.placed = true;
      block.placement = placement_index;
      placement_used = true;
      // A block that found nothing the last time is first asked as a whole:
      // one search from its centre bounds all of its sources.
      if (!block.found) {
        const Eigen::Vector3d centre = placement * block.centre;
        const double radius = block.radius + reach;
        const long t = tree.nearestWithin(centre, radius);
        const double d = t >= 0 ? std::sqrt(distanceSq(centre, targets[static_cast<std::size_t>(t)])) : radius;
        const double slack = 1e-9 + 2.5e-7 * (centre.cwiseAbs().maxCoeff() + radius + d);
        block.lower = d - block.radius - slack;
        if (block.lower >= max_distance) continue;
      }
      const std::size_t begin = b * params_.block_size, end = std::min(sources.size(), begin + params_.block_size);
      double lower = std::numeric_limits<double>::infinity();
      bool found_any = false;
      for (std::size_t k = begin; k < end; ++k) {
        const Eigen::Vector3d query = placement * sources[k];
        double source_lower = 0.0;
        const long found = nearestWithin(k, query, max_distance, targets, tree, source_lower);
        lower = std::min(lower, source_lower);
        if (found >= 0) {
          visit(k, query, found);
          found_any = true;
        }
      }
      block.lower = lower;
      block.found = found_any;
    }
    if (!placement_used) placements_.pop_back();
    if (pool_.size() > 4096 && pool_.size() > 3 * live_) compact();
  }

  /// One source: the index of the nearest of `targets` strictly within
  /// `max_distance` of `query` (source `k`, placed), or -1; `lower` is set
  /// to a lower bound on the query's distance to every target.
  long nearestWithin(std::size_t k, const Eigen::Vector3d& query, double max_distance,
                     const std::vector<Eigen::Vector3d>& targets, const Tree& tree, double& lower) {
    lower = 0.0;
    if (!(max_distance > 0)) return -1;  // nothing is within; the bounds stay as they were
    // Floats halve the memory (a joint refinement of 36 views keeps up to
    // 1,260 x 3,000 of them). Their rounding, under 1.1e-7 of the largest
    // coordinate in the stored point and 6e-8 of a stored distance, is
    // covered by a slack that grows with both: the tests stay exact at any
    // distance from the frame's origin.
    const double moved = (query - at_[k].cast<double>()).norm();
    const double around = kept(k) ? double(around_[k]) : 0.0;
    const double slack = 1e-9 + 2.5e-7 * (query.cwiseAbs().maxCoeff() + moved + double(bound_[k]) + around);
    lower = double(bound_[k]) - moved - slack;
    if (lower >= max_distance) return -1;
    // The nearest target now is no farther than the one found there, so it
    // lies within bound + 2 moved of where the surroundings were taken.
    if (kept(k) && double(bound_[k]) + 2.0 * (moved + slack) <= around - slack) {
      long best = -1;
      double best_sq = std::numeric_limits<double>::infinity();
      const std::uint32_t* it = pool_.data() + first_[k];
      for (const std::uint32_t* end = it + count_[k]; it != end; ++it) {
        const double d = distanceSq(query, targets[*it]);
        if (d < best_sq || (d == best_sq && long(*it) < best)) {
          best_sq = d;
          best = long(*it);
        }
      }
      lower = std::sqrt(best_sq);
      return best_sq < max_distance * max_distance ? best : -1;
    }
    const double radius = std::max(params_.reach, 1.0) * max_distance;
    const long found = tree.nearestWithin(query, radius);
    const double distance_sq = found >= 0 ? distanceSq(query, targets[static_cast<std::size_t>(found)]) : radius * radius;
    at_[k] = query.cast<float>();
    lower = std::sqrt(distance_sq);
    bound_[k] = static_cast<float>(lower);
    forget(k);
    if (found < 0 || !(distance_sq < max_distance * max_distance)) return -1;
    if (params_.allowance > 0) keepSurroundings(k, query, lower + 2.0 * params_.allowance * max_distance, tree);
    return found;
  }

private:
  struct Block {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // of its sources, in their frame
    double radius = 0.0;                              // around `centre`
    bool placed = false;
    bool found = false;           // a source found a target the last time its sources were searched
    double lower = 0.0;           // no target nearer any of its sources, placed by:
    std::uint32_t placement = 0;  // an index into placements_
  };

  // Summed as the tree sums it: the same verdicts at the boundary.
  static double distanceSq(const Eigen::Vector3d& q, const Eigen::Vector3d& t) {
    const double dx = q.x() - t.x(), dy = q.y() - t.y(), dz = q.z() - t.z();
    return dx * dx + dy * dy + dz * dz;
  }

  // How far `placement` can have moved any source of `block` from where
  // the block's bound holds: |dR (s - c) + dT c| <= |dR|_F r + |dT c|, plus
  // a slack for the rounding of both placements and of the bound.
  double blockMove(const Block& block, const Eigen::Isometry3d& placement) const {
    const Eigen::Isometry3d& then = placements_[block.placement];
    const Eigen::Vector3d centre_now = placement * block.centre;
    const double centre_move = (centre_now - then * block.centre).norm();
    const double turn = (placement.linear() - then.linear()).norm();
    const double move = centre_move + turn * block.radius;
    const double slack =
        1e-9 + 2.5e-7 * (centre_now.cwiseAbs().maxCoeff() + block.radius + move + std::abs(block.lower));
    return move + slack;
  }

  bool kept(std::size_t k) const { return !count_.empty() && count_[k] > 0; }

  void forget(std::size_t k) {
    if (!kept(k)) return;
    live_ -= count_[k];
    count_[k] = 0;
  }

  // The targets within `around` of `query` (source k's place now).
  void keepSurroundings(std::size_t k, const Eigen::Vector3d& query, double around, const Tree& tree) {
    if (count_.empty()) {
      first_.assign(size(), 0);
      count_.assign(size(), 0);
      around_.assign(size(), 0.0f);
    }
    // Stored rounded down: the list holds every target within the float.
    float stored = static_cast<float>(around);
    if (double(stored) > around) stored = std::nextafter(stored, 0.0f);
    tree.indicesWithinRadiusInTreeOrder(query, double(stored), scratch_);
    if (scratch_.empty()) return;
    first_[k] = static_cast<std::uint32_t>(pool_.size());
    for (std::size_t index : scratch_) pool_.push_back(static_cast<std::uint32_t>(index));
    count_[k] = static_cast<std::uint32_t>(scratch_.size());
    around_[k] = stored;
    live_ += count_[k];
  }

  // Drops the lists of forgotten surroundings from the pool.
  void compact() {
    std::vector<std::uint32_t> pool;
    pool.reserve(2 * live_);
    for (std::size_t k = 0; k < count_.size(); ++k) {
      if (count_[k] == 0) continue;
      const auto first = static_cast<std::uint32_t>(pool.size());
      pool.insert(pool.end(), pool_.begin() + first_[k], pool_.begin() + first_[k] + count_[k]);
      first_[k] = first;
    }
    pool_ = std::move(pool);
  }

  Parameters params_;
  std::vector<Eigen::Vector3f> at_;  // where each source was last searched
  std::vector<float> bound_;         // its distance to the targets there, at least (the nearest's, for a hit)
  // A hit's surroundings: count_[k] target indices from pool_[first_[k]],
  // every target within around_[k] of at_[k]. Made at the first hit.
  std::vector<std::uint32_t> first_, count_;
  std::vector<float> around_;
  std::vector<std::uint32_t> pool_;
  std::size_t live_ = 0;  // indices in pool_ still in use
  std::vector<std::size_t> scratch_;
  std::vector<Block> blocks_;
  std::vector<Eigen::Isometry3d> placements_;  // those the blocks' bounds hold at
};

}  // namespace icrkit::reconstruction
