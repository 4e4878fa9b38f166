#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <tsl/robin_map.h>

#include "dynamics/spatiotemporal_normal.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {

// The scorer's fast mode keeps the 4D moments of its window per cell, by ground class.
// Open addressing: scoring is dominated by cell look-ups, where std::unordered_map's node
// chasing costs twice as much.
using CellMap = tsl::robin_map<VoxelKey, Moments4, VoxelKeyHash>;

// The window's cell statistics: blocks of 4 x 4 x 4 cells, each a row of 64 slots into an array
// of moments. A query probes the 27 cells around it, many of them empty space. With one hash
// entry per cell (a window of the 131k-point stream: ~200k cells, a table of several MB) nearly
// every probe of a cell new to the query missed memory: a third of the scorer's time. The 27
// cells lie in 1-8 blocks, a block's slots share four cache lines, and the table of blocks is
// 64x smaller.
// The moments stay out of the blocks: with the 168-byte moments stored in the table itself it
// grew past 100 MB.
class CellTable {
 public:
  const Moments4* find(const VoxelKey& k) const {
    const auto it = blocks_.find(block_of(k));
    if (it == blocks_.end()) return nullptr;
    const std::uint32_t s = rows_[it->second].slot[slot_in_block(k)];
    return s == kEmpty ? nullptr : &moments_[s];
  }
  void add(const VoxelKey& k, const Moments4& m);
  // Takes `m` off the cell's moments; a cell left with no points is dropped (which also resets
  // its rounding residue).
  void subtract(const VoxelKey& k, const Moments4& m);
  std::size_t size() const { return cells_; }

 private:
  static constexpr std::uint32_t kEmpty = ~0u;
  struct Block {
    std::array<std::uint32_t, 64> slot;  // into moments_, kEmpty where the cell holds nothing
    std::uint32_t live = 0;              // cells of the block holding something
  };
  static std::int32_t floor4(std::int32_t v) { return (v >= 0 ? v : v - 3) / 4; }  // floor(v / 4)
  static VoxelKey block_of(const VoxelKey& k) { return {floor4(k.x), floor4(k.y), floor4(k.z)}; }
  static int slot_in_block(const VoxelKey& k) {
    return (k.x - 4 * floor4(k.x)) | (k.y - 4 * floor4(k.y)) << 2 | (k.z - 4 * floor4(k.z)) << 4;
  }

  tsl::robin_map<VoxelKey, std::uint32_t, VoxelKeyHash> blocks_;  // block -> row of rows_
  std::vector<Block> rows_;
  std::vector<std::uint32_t> free_rows_;  // rows of emptied blocks, reused first
  std::vector<Moments4> moments_;
  std::vector<std::uint32_t> free_slots_;  // slots of emptied cells, reused first
  std::size_t cells_ = 0;
};

}  // namespace cleanmap
