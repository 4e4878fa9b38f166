#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// 1 for points within `height` above the lowest point of the 3x3 block of `cell`-sized 2D grid
// cells around them (world z up), provided that lowest point is at least half a metre below
// the sensor (so roofs of large objects are not taken for ground).
std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, double sensor_z,
                                         double cell, double height);

}  // namespace cleanmap
