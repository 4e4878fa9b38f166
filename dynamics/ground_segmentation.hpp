#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"

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
  // m: points this close above the floor are the floor itself. The floor is a cell's lowest
  // point, so the surface's own points spread over a few times the range noise above it
  // (1-2 cm for spinning lidars).
  double floor_band = 0.05;
};

// Throws Error naming the bad setting.
void validate(const GroundConfig& config);

// The lowest point each cell showed in the last `scans` scans (world frame). Scans that score
// each other must agree on where the floor is: a gutter 0.2 m below the kerb, seen in one scan
// and occluded in the next, otherwise flips the pavement between ground and non-ground, and a
// point whose class differs from its neighbours' in the other scans meets only its own scan,
// which looks like something that appeared (SemanticKITTI 07: half the false positives).
struct GroundMemory {
  struct Lowest {
    float z = 0.0f;
    std::size_t scan = 0;  // when z was seen
  };
  std::size_t scans = 0;   // how long a lowest point is remembered (0: not at all)
  std::size_t now = 0;     // scans segmented so far
  tsl::robin_map<VoxelKey, Lowest, VoxelKeyHash> lowest;  // key z is 0
};

// 1 for ground points (world frame, z up), 0 for the rest. With a memory, the floor also
// rests on the lowest points of the remembered scans, and this scan's are remembered.
std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, const GroundConfig& config,
                                         GroundMemory* memory = nullptr);

// The whole log's floor (offline runs, pass 1 to pass 2): each cell's lowest point over every
// scan, below-ground returns left out per scan as segment_ground does. Beside the sensor's own
// scan the road under a car 36 m away is hidden (the car's sill is its cell's lowest point, so
// the car is "ground"); other scans saw that road before the car came or after it left.
using LogFloor = tsl::robin_map<VoxelKey, float, VoxelKeyHash>;  // key z is 0
void add_to_floor(const Eigen::Matrix3Xf& points, const GroundConfig& config, LogFloor& floor);
// segment_ground with the floor also resting on the log's lowest points (read-only: safe from
// many threads). The log's point lowers a cell as a memory's does: where it is not deeper
// under this scan's block than a slope and the band explain.
std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, const GroundConfig& config,
                                         const LogFloor& floor);

// Each point's height above its cell's floor (segment_ground: ground below `config.height`).
std::vector<float> ground_heights(const Eigen::Matrix3Xf& points, const GroundConfig& config,
                                  GroundMemory* memory = nullptr);

}  // namespace cleanmap
