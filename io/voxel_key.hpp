#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace cleanmap {

// Integer cell of a regular 3D grid, hashable for voxel hash maps (odometry's local map, the
// scorer's downsampling and sufficient statistics).
struct VoxelKey {
  std::int32_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

template <typename Vec>
VoxelKey voxel_of(const Vec& p, double inv_size) {
  return {static_cast<std::int32_t>(std::floor(p[0] * inv_size)),
          static_cast<std::int32_t>(std::floor(p[1] * inv_size)),
          static_cast<std::int32_t>(std::floor(p[2] * inv_size))};
}

// The usual three-large-primes spatial hash (Teschner et al. 2003), as KISS-ICP uses.
struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    return static_cast<std::size_t>((static_cast<std::uint32_t>(k.x) * 73856093u) ^
                                    (static_cast<std::uint32_t>(k.y) * 19349669u) ^
                                    (static_cast<std::uint32_t>(k.z) * 83492791u));
  }
};

}  // namespace cleanmap
