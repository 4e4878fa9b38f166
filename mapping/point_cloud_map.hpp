#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <array>
#include <tsl/robin_map.h>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/scan.hpp"
#include "io/voxel_key.hpp"

namespace cleanmap {

// A set of voxels as 64-bit masks of 4x4x4 voxels, hashed by block: a map cloud at 5 cm holds
// millions of voxels, and a hash set of them (32 MB and more) cost a memory miss per point;
// surfaces fill the blocks, so the blocks take a quarter of the memory and mostly stay cached.
class VoxelSet {
 public:
  bool insert(const VoxelKey& v) {  // true when the voxel was not in the set yet
    const VoxelKey block{v.x >> 2, v.y >> 2, v.z >> 2};  // arithmetic shift: floor
    auto& mask = blocks_[block];
    const std::uint64_t bit = 1ull << ((v.x & 3) | (v.y & 3) << 2 | (v.z & 3) << 4);
    if (mask & bit) return false;
    mask |= bit;
    return true;
  }

 private:
  tsl::robin_map<VoxelKey, std::uint64_t, VoxelKeyHash> blocks_;
};

// A world-frame point cloud built scan by scan. With a voxel size, only the first point that
// falls in each voxel is kept (raw measurements, not voxel centres), so memory grows with the
// mapped area, not the log length.
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
