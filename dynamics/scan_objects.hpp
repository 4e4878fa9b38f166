#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// A scan's objects as the tracker sees them: every Euclidean cluster of non-ground points, in
// the world frame, with whether the scan's own decisions call it moving.
struct ScanObject {
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();  // bounding box
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  std::uint32_t points = 0;  // downsampled points
  bool seen_moving = false;  // at least half of its points are dynamic in this scan
};

struct ScanObjects {
  std::vector<ScanObject> objects;
  std::vector<std::int32_t> of_point;  // per full-resolution point: its object, -1 = none
};

// Connected components of the included points (ids 0..k-1 in order of each component's first
// point, -1 = not included): points in the same or touching cells of a `cell` grid (26
// neighbours) are one, so points closer than `cell` always join and points more than
// 2 sqrt(3) cells apart never do directly.
std::vector<std::int32_t> grid_components(const Eigen::Matrix3Xf& points,
                                          const std::vector<std::uint8_t>& include, double cell);

// Objects from cluster ids (per downsampled point, -1 = none) and the scan's decisions. A
// cluster wider than `max_extent` (horizontally) is no object (a building, a row of parked
// cars): its points get -1, as do clusters of fewer than `min_points` points: too few to vote
// as an object in completion (ObjectRule::min_votes), too few for a centroid to follow; on the
// 131k-point stream three in four clusters are such specks, and matching them cost 4 ms a scan.
// `owner` maps each full-resolution point to its downsampled one.
ScanObjects describe_objects(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& id,
                             const std::vector<std::uint8_t>& dynamic, double max_extent,
                             int min_points, const std::vector<std::int32_t>& owner);

}  // namespace cleanmap
