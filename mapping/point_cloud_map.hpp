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
  bool insert(const VoxelKey& v) {  // true when the voxel was not in the set yet
    const VoxelKey block{v.x >> 3, v.y >> 3, v.z >> 3};  // arithmetic shift: floor
    std::uint64_t& word = blocks_[block][static_cast<std::size_t>(v.z & 7)];
    const std::uint64_t bit = 1ull << ((v.x & 7) | (v.y & 7) << 3);
    if (word & bit) return false;
    word |= bit;
    return true;
  }

 private:
  using Mask = std::array<std::uint64_t, 8>;
  tsl::robin_map<VoxelKey, Mask, VoxelKeyHash> blocks_;
};

class PointCloudMap {
 public:
  explicit PointCloudMap(double voxel_size = 0.0) : voxel_(voxel_size) {}

  // Adds the points of `scan` (world frame) with keep[i] != 0, carrying intensity, the
  // per-point score and the scan index as fields.
  void add(const Scan& scan, const std::vector<std::uint8_t>& keep,
           const std::vector<float>& score, std::size_t scan_index);

  std::size_t size() const { return x_.size(); }

  // Writes x y z [intensity] score scan (PCD or PLY by extension).
  void write(const std::filesystem::path& file) const;

 private:
  double voxel_;
  VoxelSet seen_;
  std::vector<float> x_, y_, z_, intensity_, score_, scan_;
  bool has_intensity_ = true;
};

}  // namespace cleanmap
