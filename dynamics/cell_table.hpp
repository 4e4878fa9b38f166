#pragma once

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

// The window's cell statistics: a compact cell -> slot table in front of an array of moments.
// A query probes up to 27 cells, many of them empty space; with the 168-byte moments stored
// in the buckets themselves the table grew past 100 MB and nearly every probe missed memory.
struct CellTable {
  tsl::robin_map<VoxelKey, std::uint32_t, VoxelKeyHash> slot;
  std::vector<Moments4> moments;
  std::vector<std::uint32_t> unused;  // slots of emptied cells, reused first

  const Moments4* find(const VoxelKey& k) const {
    const auto it = slot.find(k);
    return it == slot.end() ? nullptr : &moments[it->second];
  }
  void add(const VoxelKey& k, const Moments4& m) {
    const auto [it, fresh] = slot.try_emplace(k, 0u);
    if (!fresh) {
      moments[it->second] += m;
    } else if (unused.empty()) {
      it.value() = static_cast<std::uint32_t>(moments.size());
      moments.push_back(m);
    } else {
      it.value() = unused.back();
      unused.pop_back();
      moments[it->second] = m;
    }
  }
  void subtract(const VoxelKey& k, const Moments4& m) {
    const auto it = slot.find(k);
    if (it == slot.end()) return;
    Moments4& c = moments[it->second];
    c -= m;
    // Dropping emptied cells also resets their rounding residue.
    if (c.n < 0.5) {
      unused.push_back(it->second);
      slot.erase(it);
    }
  }
  std::size_t size() const { return slot.size(); }
};

}  // namespace cleanmap
