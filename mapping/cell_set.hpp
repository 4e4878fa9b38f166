#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"

namespace cleanmap {

// A set of OctoMap cells (16-bit keys per axis) for one scan's update: a bitmap per 32^3 tile,
// tiles found by hash, the last tile cached. Rays and scan rows visit neighbouring cells in a
// row, so most inserts are one cached bit test; a hash set of keys paid a cache miss each.
// It also hands the cells back in octree (Morton) order without a sort, which makes the
// OctoMap updates that follow walk the same branches one after another.
class CellSet {
 public:
  using Key = std::array<std::uint16_t, 3>;

  // True when the cell was not in the set yet.
  bool insert(const Key& k);
  bool contains(const Key& k) const;
  // Every cell of this set that is in `in` and not in `out`, tile by tile, 64 cells to a word
  // (any order).
  void for_each_also_in(const CellSet& in, const CellSet& out, const std::function<void(const Key&)>& visit) const;
  std::size_t size() const { return size_; }

  // Every cell, in octree order (the order of a depth-first walk of the OctoMap).
  template <typename F>
  void for_each_in_tree_order(F&& visit) const;

 private:
  static constexpr int kBits = 5;  // tile edge 32 cells
  struct Tile {
    std::uint64_t morton = 0;  // of the tile coordinates: sorts tiles in tree order
    Key base{};
    std::array<std::uint64_t, (1u << (3 * kBits)) / 64> bits{};
  };
  std::int64_t find(const Key& k) const;  // index in tiles_, -1 when absent
  std::size_t tile_for(const Key& k);     // index in tiles_, made when absent
  const Tile* tile_of(const Key& k) const;  // nullptr when absent; no cache, thread-safe

  tsl::robin_map<std::uint64_t, std::uint32_t> index_;  // tile coordinates -> tiles_
  std::vector<Tile> tiles_;
  // Tiles looked up lately, direct-mapped as in Reader (tile id + 1, 0 = empty): makes even
  // contains() mutate, so one thread at a time. One slot (the last tile) left a ray's walk a
  // hash probe at every tile border; its rays fan out from one origin and keep coming back.
  static constexpr std::size_t kCacheSlots = 64;  // tile_slot's 6 bits
  mutable std::array<std::uint64_t, kCacheSlots> cache_id_{};
  mutable std::array<std::uint32_t, kCacheSlots> cache_tile_{};
  std::size_t size_ = 0;

 public:
  // Lookups with a tile cache of their own: one Reader per thread, many threads on one set
  // (contains() caches in the set itself).
  class Reader {
   public:
    explicit Reader(const CellSet& set) : set_(set) {}
    bool contains(const Key& k);

   private:
    // Direct-mapped by tile: the rays of a scan fan out from one origin, so a few tiles (those
    // near the sensor) are asked again and again between the others.
    const CellSet& set_;
    std::array<std::uint64_t, kCacheSlots> id_{};  // tile id + 1, 0 = empty, as the set's own
    std::array<const Tile*, kCacheSlots> tile_{};
  };
};

namespace cell_set_detail {
// The 5 bits of an axis spread to every third bit, by table: a ray's walk asks for three
// of these per cell (its walked set, the hit set, the crossed set), and the shift-and-mask
// spread of morton_code was the largest share of VisibilityMap::cast's instructions.
inline constexpr std::array<std::uint16_t, 32> kSpread5 = [] {
  std::array<std::uint16_t, 32> t{};
  for (std::uint32_t v = 0; v < 32; ++v) {
    std::uint32_t s = 0;
    for (int b = 0; b < 5; ++b) s |= ((v >> b) & 1u) << (3 * b);
    t[v] = static_cast<std::uint16_t>(s);
  }
  return t;
}();
// Of the low 5 bits of each axis (morton_code of them).
inline std::uint32_t local_morton(const CellSet::Key& k) {
  constexpr std::uint16_t kLow = (1u << 5) - 1;
  return static_cast<std::uint32_t>(kSpread5[k[0] & kLow]) | static_cast<std::uint32_t>(kSpread5[k[1] & kLow]) << 1 |
         static_cast<std::uint32_t>(kSpread5[k[2] & kLow]) << 2;
}
CellSet::Key local_cell(std::uint32_t morton);  // inverse
inline std::uint64_t tile_id(const CellSet::Key& k) {
  return static_cast<std::uint64_t>(k[0] >> 5) << 22 | static_cast<std::uint64_t>(k[1] >> 5) << 11 | (k[2] >> 5);
}
// The cache slot of a tile (of 64): the low 2 bits of each tile coordinate.
inline std::size_t tile_slot(const CellSet::Key& k) {
  return static_cast<std::size_t>((k[0] >> 5 & 3) | (k[1] >> 5 & 3) << 2 | (k[2] >> 5 & 3) << 4);
}
}  // namespace cell_set_detail

// Inline: a ray's walk asks these once per cell it crosses.
inline std::int64_t CellSet::find(const Key& k) const {
  const auto id = cell_set_detail::tile_id(k) + 1;
  const auto slot = cell_set_detail::tile_slot(k);
  if (cache_id_[slot] != id) {
    const auto it = index_.find(id - 1);
    if (it == index_.end()) return -1;
    cache_id_[slot] = id;
    cache_tile_[slot] = it->second;
  }
  return cache_tile_[slot];
}

inline bool CellSet::insert(const Key& k) {
  std::int64_t t = find(k);
  if (t < 0) t = static_cast<std::int64_t>(tile_for(k));  // a new tile: rare
  const auto m = cell_set_detail::local_morton(k);
  auto& word = tiles_[static_cast<std::size_t>(t)].bits[m >> 6];
  const std::uint64_t bit = 1ull << (m & 63);
  if (word & bit) return false;
  word |= bit;
  ++size_;
  return true;
}

inline bool CellSet::contains(const Key& k) const {
  const auto t = find(k);
  if (t < 0) return false;
  const auto m = cell_set_detail::local_morton(k);
  return (tiles_[static_cast<std::size_t>(t)].bits[m >> 6] >> (m & 63)) & 1u;
}

inline bool CellSet::Reader::contains(const Key& k) {
  const auto id = cell_set_detail::tile_id(k) + 1;
  const std::size_t slot = cell_set_detail::tile_slot(k);
  if (id_[slot] != id) {
    id_[slot] = id;
    tile_[slot] = set_.tile_of(k);
  }
  const Tile* tile = tile_[slot];
  if (tile == nullptr) return false;
  const auto m = cell_set_detail::local_morton(k);
  return (tile->bits[m >> 6] >> (m & 63)) & 1u;
}

template <typename F>
void CellSet::for_each_in_tree_order(F&& visit) const {
  std::vector<std::uint32_t> order(tiles_.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return tiles_[a].morton < tiles_[b].morton; });
  for (const auto t : order) {
    const Tile& tile = tiles_[t];
    for (std::uint32_t w = 0; w < tile.bits.size(); ++w) {
      for (std::uint64_t word = tile.bits[w]; word != 0; word &= word - 1) {
        const auto local = cell_set_detail::local_cell(w * 64 + static_cast<std::uint32_t>(__builtin_ctzll(word)));
        visit(Key{static_cast<std::uint16_t>(tile.base[0] | local[0]), static_cast<std::uint16_t>(tile.base[1] | local[1]),
                  static_cast<std::uint16_t>(tile.base[2] | local[2])});
      }
    }
  }
}

}  // namespace cleanmap
