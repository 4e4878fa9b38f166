#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <array>
#include <tsl/robin_map.h>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/scan.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {

// A set of voxels as 512-bit masks of 8x8x8 voxels (one cache line), hashed by block: a map
// cloud at 5 cm holds millions of voxels, and a hash set of them (32 MB and more) cost a
// memory miss per point; surfaces fill the blocks, so the blocks take a fraction of the memory
// and mostly stay cached.
class VoxelSet {
 public:
  VoxelSet() = default;
  // The last block's pointer points into this set's table: no copies or moves.
  VoxelSet(const VoxelSet&) = delete;
  VoxelSet& operator=(const VoxelSet&) = delete;

  bool insert(const VoxelKey& v) {  // true when the voxel was not in the set yet
    const VoxelKey block{v.x >> 3, v.y >> 3, v.z >> 3};  // arithmetic shift: floor
    // Consecutive points of a ring along one surface share a block (0.4 m at 5 cm): the last
    // block's mask answers without the table, whose probe misses the cache. Measured alone:
    // without it the online run took 1.7% more CPU (bench/compare_cpu.sh, 6 pairs, 5 of them
    // slower). The pointer is the table's answer since its last insertion, which is the only
    // thing that moves masks.
    if (!last_mask_ || !(block == last_block_)) {
      last_mask_ = &blocks_[block];
      last_block_ = block;
    }
    std::uint64_t& word = (*last_mask_)[static_cast<std::size_t>(v.z & 7)];
    const std::uint64_t bit = 1ull << ((v.x & 7) | (v.y & 7) << 3);
    if (word & bit) return false;
    word |= bit;
    return true;
  }

 private:
  using Mask = std::array<std::uint64_t, 8>;
  tsl::robin_map<VoxelKey, Mask, VoxelKeyHash> blocks_;
  VoxelKey last_block_;
  Mask* last_mask_ = nullptr;
};

// A map cloud: the kept points of every scan, with their fields. Memory follows the points
// kept: each scan's points are one block of rows of exactly its size (x y z intensity score
// scan, float32), as the files hold them. In growing vectors of each field, doubling and
// reallocating, and with the copies made to write them, a DynamicMap-layout street's clouds
// (5.5 M static points) had been 41 % of the run's peak heap (heaptrack: 189 MB of growth,
// 131 MB of write copies, 44 MB of field copies, of 641 MB).
class PointCloudMap {
 public:
  explicit PointCloudMap(double voxel_size = 0.0) : voxel_(voxel_size) {}

  // Adds the points of `scan` (world frame) with keep[i] != 0, carrying intensity, the
  // per-point score and the scan index as fields.
  void add(const Scan& scan, const std::vector<std::uint8_t>& keep,
           const std::vector<float>& score, std::size_t scan_index);

  std::size_t size() const { return size_; }
  // The points kept so far, one column each (a copy: the cloud keeps them as rows).
  Eigen::Matrix3Xf points() const;

  // Writes x y z [intensity] score scan to each file (PCD or PLY by extension), from one
  // packed copy of the points.
  void write(const std::vector<std::filesystem::path>& files) const;
  void write(const std::filesystem::path& file) const { write(std::vector<std::filesystem::path>{file}); }

 private:
  static constexpr std::size_t kRow = 6;  // x y z intensity score scan
  double voxel_;
  VoxelSet seen_;
  std::vector<std::vector<float>> blocks_;  // one per add() that kept points
  std::size_t size_ = 0;
  bool has_intensity_ = true;  // every scan added had intensity
};

}  // namespace cleanmap
