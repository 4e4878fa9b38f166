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

// The three coordinates' low 21 bits in one word: a hash's input (voxels 2^21 apart share it).
inline std::uint64_t packed_key(const VoxelKey& k) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x) & 0x1FFFFFu) << 42) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y) & 0x1FFFFFu) << 21) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z) & 0x1FFFFFu));
}

// The packed key mixed by the splitmix64 finaliser: power-of-two open-addressing tables index
// by the low bits, which the plain XOR-of-primes spatial hash leaves poorly mixed.
struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    std::uint64_t h = packed_key(k);
    h ^= h >> 30;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 27;
    h *= 0x94d049bb133111ebULL;
    h ^= h >> 31;
    return static_cast<std::size_t>(h);
  }
};

// Morton (Z-order) interleave of three 21-bit values, x in the lowest bit: sorting by it
// visits space block by block, as a depth-first walk of an octree does.
inline std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}
inline std::uint64_t morton_code(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  return spread_bits(z) << 2 | spread_bits(y) << 1 | spread_bits(x);
}
// Of a voxel: coordinates offset by 2^20, so that the order holds across zero.
inline std::uint64_t morton_code(const VoxelKey& k) {
  constexpr std::int64_t kOffset = 1 << 20;
  return morton_code(static_cast<std::uint64_t>(k.x + kOffset), static_cast<std::uint64_t>(k.y + kOffset),
                     static_cast<std::uint64_t>(k.z + kOffset));
}

}  // namespace cleanmap
