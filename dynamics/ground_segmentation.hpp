#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// Where the ground is, without knowing the sensor's height (a robot at floor level, a lidar
// on a 4 m mast and poses whose z is not the mount height all look alike to it).
struct GroundConfig {
  double cell = 1.0;        // m: 2D grid (world x, y) of lowest points
  double height = 0.25;     // m: points this close above the local ground are ground
  // A cell's floor is the lowest point around it (3x3 cells), and never above the lowest
  // surface a walkable slope reaches from the lowest points within `reach`: a car's roof 1.5 m
  // above the road is not ground when road is seen within `reach`.
  double max_slope = 0.3;   // rise per metre (17 degrees)
  double reach = 3.0;       // m: roofs of objects up to twice this wide are told from ground
};

// Throws Error naming the bad setting.
void validate(const GroundConfig& config);

// 1 for ground points (world frame, z up), 0 for the rest.
std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, const GroundConfig& config);

}  // namespace cleanmap
