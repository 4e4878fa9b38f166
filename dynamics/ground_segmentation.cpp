#include "dynamics/ground_segmentation.hpp"

#include <cmath>
#include <limits>
#include <unordered_map>

namespace cleanmap {
namespace {

std::uint64_t cell_key(std::int32_t x, std::int32_t y) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) |
         static_cast<std::uint32_t>(y);
}

}  // namespace

std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, double sensor_z,
                                         double cell, double height) {
  const double inv = 1.0 / cell;
  const auto n = static_cast<std::size_t>(points.cols());
  std::vector<std::int32_t> cx(n), cy(n);
  std::unordered_map<std::uint64_t, float> lowest;
  lowest.reserve(n / 4 + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const auto p = points.col(static_cast<Eigen::Index>(i));
    cx[i] = static_cast<std::int32_t>(std::floor(p.x() * inv));
    cy[i] = static_cast<std::int32_t>(std::floor(p.y() * inv));
    auto [it, fresh] = lowest.try_emplace(cell_key(cx[i], cy[i]), p.z());
    if (!fresh) it->second = std::min(it->second, p.z());
  }
  std::vector<std::uint8_t> ground(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    float floor_z = std::numeric_limits<float>::infinity();
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const auto it = lowest.find(cell_key(cx[i] + dx, cy[i] + dy));
        if (it != lowest.end()) floor_z = std::min(floor_z, it->second);
      }
    }
    const float z = points(2, static_cast<Eigen::Index>(i));
    ground[i] = (floor_z < sensor_z - 0.5 && z - floor_z < height) ? 1 : 0;
  }
  return ground;
}

}  // namespace cleanmap
