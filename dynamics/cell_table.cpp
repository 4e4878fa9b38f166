#include "dynamics/cell_table.hpp"

namespace cleanmap {

void CellTable::add(const VoxelKey& k, const Moments4& m) {
  const auto [it, fresh] = blocks_.try_emplace(block_of(k), 0u);
  if (fresh) {
    if (free_rows_.empty()) {
      it.value() = static_cast<std::uint32_t>(rows_.size());
      rows_.emplace_back();
    } else {
      it.value() = free_rows_.back();
      free_rows_.pop_back();
    }
    Block& b = rows_[it->second];
    b.slot.fill(kEmpty);
    b.live = 0;
  }
  Block& b = rows_[it->second];
  std::uint32_t& s = b.slot[slot_in_block(k)];
  if (s != kEmpty) {
    moments_[s] += m;
    return;
  }
  if (free_slots_.empty()) {
    s = static_cast<std::uint32_t>(moments_.size());
    moments_.push_back(m);
  } else {
    s = free_slots_.back();
    free_slots_.pop_back();
    moments_[s] = m;
  }
  ++b.live;
  ++cells_;
}

void CellTable::subtract(const VoxelKey& k, const Moments4& m) {
  const auto it = blocks_.find(block_of(k));
  if (it == blocks_.end()) return;
  Block& b = rows_[it->second];
  std::uint32_t& s = b.slot[slot_in_block(k)];
  if (s == kEmpty) return;
  Moments4& c = moments_[s];
  c -= m;
  if (c.n >= 0.5) return;
  free_slots_.push_back(s);
  s = kEmpty;
  --cells_;
  if (--b.live == 0) {
    free_rows_.push_back(it->second);
    blocks_.erase(it);
  }
}

}  // namespace cleanmap
