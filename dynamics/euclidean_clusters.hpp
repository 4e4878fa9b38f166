#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// Connected components of the points with include[i] != 0, linking points closer than
// `radius`. Returns a cluster id per point (-1 for excluded points); ids are 0..k-1, numbered
// by their lowest point index, so the result does not depend on search order.
std::vector<std::int32_t> euclidean_clusters(const Eigen::Matrix3Xf& points,
                                             const std::vector<std::uint8_t>& include,
                                             float radius);

}  // namespace cleanmap
