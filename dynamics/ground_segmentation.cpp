#include "dynamics/ground_segmentation.hpp"

#include <cmath>

#include <tsl/robin_map.h>

#include "io/voxel_key.hpp"

namespace cleanmap {

std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, double sensor_z,
                                         double cell, double height) {
  const double inv = 1.0 / cell;
  const auto n = static_cast<std::size_t>(points.cols());
  std::vector<VoxelKey> key(n);
  tsl::robin_map<VoxelKey, float, VoxelKeyHash> lowest;
  lowest.reserve(n / 16 + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const auto p = points.col(static_cast<Eigen::Index>(i));
    key[i] = {static_cast<std::int32_t>(std::floor(p.x() * inv)),
              static_cast<std::int32_t>(std::floor(p.y() * inv)), 0};
    auto [it, fresh] = lowest.try_emplace(key[i], p.z());
    if (!fresh) it.value() = std::min(it->second, p.z());
  }
  // The local floor of each cell: the lowest point in it and its 8 neighbours.
  tsl::robin_map<VoxelKey, float, VoxelKeyHash> floor;
  floor.reserve(lowest.size());
  for (const auto& [k, z] : lowest) {
    float floor_z = z;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const auto it = lowest.find(VoxelKey{k.x + dx, k.y + dy, 0});
        if (it != lowest.end()) floor_z = std::min(floor_z, it->second);
      }
    }
    floor.emplace(k, floor_z);
  }
  std::vector<std::uint8_t> ground(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const float floor_z = floor.find(key[i])->second;
    const float z = points(2, static_cast<Eigen::Index>(i));
    ground[i] = (floor_z < sensor_z - 0.5 && z - floor_z < height) ? 1 : 0;
  }
  return ground;
}

}  // namespace cleanmap
