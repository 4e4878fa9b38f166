#include "mapping/cell_set.hpp"

#include "geometry/voxel_key.hpp"

namespace cleanmap {
namespace {

constexpr std::uint16_t kLow = (1u << 5) - 1;
using cell_set_detail::tile_id;

std::uint64_t compact(std::uint64_t v) {
  v &= 0x1249249249249249ull;
  v = (v ^ (v >> 2)) & 0x10C30C30C30C30C3ull;
  v = (v ^ (v >> 4)) & 0x100F00F00F00F00Full;
  v = (v ^ (v >> 8)) & 0x1F0000FF0000FFull;
  v = (v ^ (v >> 16)) & 0x1F00000000FFFFull;
  v = (v ^ (v >> 32)) & 0x1FFFFF;
  return v;
}

}  // namespace

namespace cell_set_detail {
CellSet::Key local_cell(std::uint32_t m) {
  return {static_cast<std::uint16_t>(compact(m)), static_cast<std::uint16_t>(compact(m >> 1)),
          static_cast<std::uint16_t>(compact(m >> 2))};
}
}  // namespace cell_set_detail

std::size_t CellSet::tile_for(const Key& k) {
  auto t = find(k);
  if (t < 0) {
    Tile tile;
    tile.base = {static_cast<std::uint16_t>(k[0] & ~kLow), static_cast<std::uint16_t>(k[1] & ~kLow),
                 static_cast<std::uint16_t>(k[2] & ~kLow)};
    tile.morton = morton_code(k[0] >> 5, k[1] >> 5, k[2] >> 5);
    t = static_cast<std::int64_t>(tiles_.size());
    tiles_.push_back(tile);
    index_.emplace(tile_id(k), static_cast<std::uint32_t>(t));
    cache_id_[cell_set_detail::tile_slot(k)] = tile_id(k) + 1;
    cache_tile_[cell_set_detail::tile_slot(k)] = static_cast<std::uint32_t>(t);
  }
  return static_cast<std::size_t>(t);
}

const CellSet::Tile* CellSet::tile_of(const Key& k) const {
  const auto it = index_.find(tile_id(k));
  return it == index_.end() ? nullptr : &tiles_[it->second];
}

void CellSet::for_each_also_in(const CellSet& in, const CellSet& out,
                               const std::function<void(const Key&)>& visit) const {
  for (const Tile& tile : tiles_) {
    const Tile* a = in.tile_of(tile.base);
    if (a == nullptr) continue;
    const Tile* b = out.tile_of(tile.base);
    for (std::size_t w = 0; w < tile.bits.size(); ++w) {
      std::uint64_t word = tile.bits[w] & a->bits[w];
      if (b != nullptr) word &= ~b->bits[w];
      for (; word != 0; word &= word - 1) {
        const auto local = cell_set_detail::local_cell(static_cast<std::uint32_t>(w * 64) +
                                                       static_cast<std::uint32_t>(__builtin_ctzll(word)));
        visit(Key{static_cast<std::uint16_t>(tile.base[0] | local[0]), static_cast<std::uint16_t>(tile.base[1] | local[1]),
                  static_cast<std::uint16_t>(tile.base[2] | local[2])});
      }
    }
  }
}

}  // namespace cleanmap
