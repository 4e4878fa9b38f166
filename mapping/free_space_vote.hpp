#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "dynamics/object_rule.hpp"

namespace cleanmap {

// The default rule: a third of a cluster's 0.2 m voxels, and 5 of them (a metre of a car's
// side), in cells seen free.
inline constexpr ObjectRule kFreeSpaceRule{0.6, 5, 0.3, 12.0, 0.15};

// The occupancy opinion on one scan (world frame), per object: Euclidean clusters of its
// non-ground points (on a `voxel` subsample: 0.2 m for streets, a few cm for a tabletop) are dynamic when enough of them (`rule`:
// votes are the subsample points in cells the map had seen free, `hits_in_free_space` answers
// that) do; over-large clusters are split as the rule says. Returns 1 per point in such
// clusters. Normals miss cars driving past (their sides move within their own planes); free
// space does not.
// `ground_of` splits the subsample into ground (1) and the rest; a full-resolution point
// takes the answer of its voxel's subsample point.
using FreeSpaceQuery = std::function<std::vector<std::uint8_t>(const Eigen::Matrix3Xf&)>;
using GroundQuery = std::function<std::vector<std::uint8_t>(const Eigen::Matrix3Xf&)>;
std::vector<std::uint8_t> free_space_objects(const Eigen::Matrix3Xf& points,
                                             const GroundQuery& ground_of,
                                             const FreeSpaceQuery& hits_in_free_space,
                                             const ObjectRule& rule, double voxel = 0.2);

}  // namespace cleanmap
