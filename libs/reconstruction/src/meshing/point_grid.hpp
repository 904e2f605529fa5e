#pragma once
// Uniform grid over a fixed set of oriented points for radius queries no
// larger than the cell size: a query looks at the 27 cells around it only.
// Ball pivoting asks millions of such small queries of one size per radius;
// a grid that stores each point's position and normal cell by cell answers
// them from contiguous memory, where a kd-tree descends and then gathers
// from all over the input arrays.

#include <icrkit/core/morton_order.hpp>

#include <Eigen/Core>

#include <cmath>
#include <algorithm>
#include <cstddef>
#include <utility>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace icrkit::reconstruction {

class PointGrid {
public:
  struct Entry {
    Eigen::Vector3d position;
    Eigen::Vector3d normal;
    std::uint32_t index;
  };

  PointGrid() = default;

  /// `normals` may be empty (entries then hold zero normals); points with a
  /// non-zero `skip` entry are left out (`skip` may be empty).
  PointGrid(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
            const std::vector<std::uint8_t>& skip, double cell_size) {
    build(points, normals, skip, cell_size);
  }

  /// (Re)builds the grid, reusing the memory of an earlier build.
  void build(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
             const std::vector<std::uint8_t>& skip, double cell_size) {
    if (!(cell_size > 0.0) || !std::isfinite(cell_size)) throw std::invalid_argument("PointGrid: cell size must be > 0");
    const std::size_t n = points.size();
    auto skipped = [&](std::size_t i) { return !skip.empty() && skip[i]; };
    origin_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d top = -origin_;
    for (std::size_t i = 0; i < n; ++i)
      if (!skipped(i)) {
        origin_ = origin_.cwiseMin(points[i]);
        top = top.cwiseMax(points[i]);
      }
    // Cells are addressed by 32-bit coordinates; a cloud spread over more
    // cells than that gets coarser cells (correct, only slower).
    cell_ = std::max(cell_size, (top - origin_).maxCoeff() / 1e9);
    inverse_ = 1.0 / cell_;

    // Count the points of each cell in a table that grows with the cells
    // found, then lay the cells out in Morton order in a table sized for
    // them: neighbouring cells then sit close together in memory.
    keys_.resize(n);
    resize(n / 4);
    std::size_t cells = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (skipped(i)) continue;
      keys_[i] = keyOf(points[i]);
      std::size_t s = find(keys_[i]);
      if (!slots_[s].used) {
        if (2 * (cells + 1) > slots_.size()) {
          grow();
          s = find(keys_[i]);
        }
        slots_[s].used = true;
        slots_[s].key = keys_[i];
        ++cells;
      }
      ++slots_[s].count;
    }
    cells_.clear();
    for (const Slot& slot : slots_)
      if (slot.used) cells_.emplace_back(mortonCode(slot.key.x, slot.key.y, slot.key.z), slot);
    std::sort(cells_.begin(), cells_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    resize(2 * cells_.size());
    std::uint32_t offset = 0;
    for (const auto& cell : cells_) {
      Slot& slot = slots_[find(cell.second.key)];
      slot = cell.second;
      slot.begin = offset;
      offset += slot.count;
      slot.count = 0;
    }
    entries_.resize(offset);
    // Filled in index order: each cell lists its points ascending.
    for (std::size_t i = 0; i < n; ++i) {
      if (skipped(i)) continue;
      Slot& slot = slots_[find(keys_[i])];
      Entry& entry = entries_[slot.begin + slot.count++];
      entry.position = points[i];
      entry.normal = normals.empty() ? Eigen::Vector3d::Zero() : normals[i];
      entry.index = static_cast<std::uint32_t>(i);
    }
  }

  double cellSize() const { return cell_; }

  /// Calls visit(entry, squared_distance) for every point within `radius`
  /// (<= cellSize()) of `query`, cell by cell.
  template <typename Visit>
  void forEachWithin(const Eigen::Vector3d& query, double radius, Visit&& visit) const {
    const double r2 = radius * radius;
    // Only the cells the query's bounding box overlaps: about 8 rather
    // than 27 when the radius is near half a cell.
    const Key lo = keyOf(query - Eigen::Vector3d::Constant(radius));
    const Key hi = keyOf(query + Eigen::Vector3d::Constant(radius));
    for (std::int32_t z = lo.z; z <= hi.z; ++z)
      for (std::int32_t y = lo.y; y <= hi.y; ++y)
        for (std::int32_t x = lo.x; x <= hi.x; ++x) {
          const Slot& slot = slots_[find(Key{x, y, z})];
          for (std::uint32_t at = slot.begin, end = slot.begin + slot.count; at < end; ++at) {
            const double d2 = (entries_[at].position - query).squaredNorm();
            if (d2 <= r2) visit(entries_[at], d2);
          }
        }
  }

  /// The entries within `radius` of `query` into `out` (cleared first), in
  /// no particular order.
  void entriesWithin(const Eigen::Vector3d& query, double radius, std::vector<const Entry*>& out) const {
    out.clear();
    forEachWithin(query, radius, [&out](const Entry& e, double) { out.push_back(&e); });
  }

private:
  struct Key {
    std::int32_t x = 0, y = 0, z = 0;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Slot {
    Key key;
    std::uint32_t begin = 0, count = 0;
    bool used = false;
  };

  Key keyOf(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d c = ((p - origin_) * inverse_).array().floor();
    // Queries may lie outside the points' box; clamping keeps the key
    // representable (far cells are empty either way).
    auto clamp = [](double v) { return static_cast<std::int32_t>(std::max(-2e9, std::min(2e9, v))); };
    return {clamp(c.x()), clamp(c.y()), clamp(c.z())};
  }

  void resize(std::size_t minimum) {
    std::size_t capacity = 16;
    while (capacity < minimum) capacity <<= 1;
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
  }

  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    resize(2 * old.size());
    for (const Slot& slot : old)
      if (slot.used) slots_[find(slot.key)] = slot;
  }

  // The slot holding `key`, or the empty slot where it would go (linear
  // probing; the table is at most half full, so probing ends).
  std::size_t find(const Key& key) const {
    std::uint64_t h = static_cast<std::uint32_t>(key.x) * 0x9E3779B97F4A7C15ULL;
    h ^= static_cast<std::uint32_t>(key.y) * 0xC2B2AE3D27D4EB4FULL;
    h ^= static_cast<std::uint32_t>(key.z) * 0x165667B19E3779F9ULL;
    h ^= h >> 29;
    std::size_t s = static_cast<std::size_t>(h) & mask_;
    while (slots_[s].used && !(slots_[s].key == key)) s = (s + 1) & mask_;
    return s;
  }

  double cell_ = 1.0, inverse_ = 1.0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  std::vector<Key> keys_;
  std::vector<std::pair<std::uint64_t, Slot>> cells_;
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::vector<Entry> entries_;
};

}  // namespace icrkit::reconstruction
