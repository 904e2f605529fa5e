#pragma once
// Private to the fusion: a set of OctoMap keys as a bitmap over a box of
// keys (the crop box), with a hash set for the few keys outside it. A
// scan's rays insert tens of keys each, nearly all already there (rays of
// neighbouring pixels cross the same voxels): setting a bit costs a
// fraction of a hash-set insertion, and the set is read back in grid order.

#include <octomap/OcTreeKey.h>

#include <cstdint>
#include <vector>

namespace icrkit::reconstruction {

class KeyBitmap {
public:
  KeyBitmap() = default;
  // Keys from `min` to `max` (inclusive, per axis) go to the bitmap.
  KeyBitmap(const octomap::OcTreeKey& min, const octomap::OcTreeKey& max) : min_(min) {
    for (int a = 0; a < 3; ++a) size_[a] = static_cast<std::uint32_t>(max[a] - min[a] + 1);
    bits_.assign((static_cast<std::size_t>(size_[0]) * size_[1] * size_[2] + 63) / 64, 0);
  }

  void insert(const octomap::OcTreeKey& key) {
    std::size_t slot;
    if (slotOf(key, slot))
      bits_[slot >> 6] |= std::uint64_t{1} << (slot & 63);
    else
      outside_.insert(key);
  }

  bool contains(const octomap::OcTreeKey& key) const {
    std::size_t slot;
    if (slotOf(key, slot)) return (bits_[slot >> 6] >> (slot & 63)) & 1;
    return outside_.find(key) != outside_.end();
  }

  // Every key once: the bitmap's in grid order, then those outside it.
  template <class Visit>
  void forEach(Visit visit) const {
    for (std::size_t w = 0; w < bits_.size(); ++w)
      for (std::uint64_t word = bits_[w]; word != 0; word &= word - 1) {
        const std::size_t slot = (w << 6) + static_cast<std::size_t>(__builtin_ctzll(word));
        const std::size_t x = slot % size_[0], y = (slot / size_[0]) % size_[1], z = slot / (std::size_t{size_[0]} * size_[1]);
        visit(octomap::OcTreeKey(static_cast<octomap::key_type>(min_[0] + x), static_cast<octomap::key_type>(min_[1] + y),
                                 static_cast<octomap::key_type>(min_[2] + z)));
      }
    for (const octomap::OcTreeKey& key : outside_) visit(key);
  }

  std::size_t size() const {
    std::size_t count = outside_.size();
    for (std::uint64_t word : bits_) count += static_cast<std::size_t>(__builtin_popcountll(word));
    return count;
  }

private:
  bool slotOf(const octomap::OcTreeKey& key, std::size_t& slot) const {
    const std::uint32_t x = static_cast<std::uint32_t>(key[0] - min_[0]), y = static_cast<std::uint32_t>(key[1] - min_[1]),
                        z = static_cast<std::uint32_t>(key[2] - min_[2]);
    // Below min wraps around to a large value: outside as well.
    if (key[0] < min_[0] || key[1] < min_[1] || key[2] < min_[2] || x >= size_[0] || y >= size_[1] || z >= size_[2])
      return false;
    slot = (static_cast<std::size_t>(z) * size_[1] + y) * size_[0] + x;
    return true;
  }

  octomap::OcTreeKey min_{0, 0, 0};
  std::uint32_t size_[3] = {0, 0, 0};
  std::vector<std::uint64_t> bits_;
  octomap::KeySet outside_;
};

}  // namespace icrkit::reconstruction
