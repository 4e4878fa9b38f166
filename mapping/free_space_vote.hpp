#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

namespace cleanmap {

// The occupancy opinion on one scan (world frame), per object: Euclidean clusters of its
// non-ground points (on a 0.2 m voxel subsample) are dynamic when at least `fraction` of them,
// and `min_hits` points, fall in cells the map had seen free (`hits_in_free_space` answers
// that for the subsample). Returns 1 per point in such clusters. Normals miss cars driving
// past (their sides move within their own planes); free space does not.
// `ground_of` splits the subsample into ground (1) and the rest; a full-resolution point
// takes the answer of its voxel's subsample point.
using FreeSpaceQuery = std::function<std::vector<std::uint8_t>(const Eigen::Matrix3Xf&)>;
using GroundQuery = std::function<std::vector<std::uint8_t>(const Eigen::Matrix3Xf&)>;
std::vector<std::uint8_t> free_space_objects(const Eigen::Matrix3Xf& points,
                                             const GroundQuery& ground_of,
                                             const FreeSpaceQuery& hits_in_free_space,
                                             double fraction, int min_hits = 5,
                                             float cluster_radius = 0.6f,
                                             double max_extent = 12.0);

}  // namespace cleanmap
