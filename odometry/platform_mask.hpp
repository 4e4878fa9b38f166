#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <tsl/robin_set.h>

#include "io/scan.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {

// The recording platform (the vehicle's body, the sensor mount, a backpack) moves with the
// sensor: its returns keep their sensor-frame position in every scan, which the spatiotemporal
// scorer reads as motion at the platform's speed, and which pulls odometry towards standing
// still. On the Pandar64 street those points were more than half of all false positives
// within 20 m.
struct PlatformMaskConfig {
  bool automatic = true;      // learn the mask from the first scans
  int learn_scans = 20;       // how many scans it is learnt from (fewer if the log is shorter)
  double max_range = 3.0;     // m: only points this close can be the platform
  double voxel = 0.2;         // m: sensor-frame cells
  double min_share = 0.9;     // of the learning scans a cell must be occupied in
  // Sensor-frame box whose points are always masked: xmin ymin zmin xmax ymax zmax (m);
  // empty = none.
  std::vector<double> crop_box;
};

// Throws Error naming the bad setting.
void validate(const PlatformMaskConfig& config);

struct PlatformMask {
  tsl::robin_set<VoxelKey, VoxelKeyHash> cells;  // learnt cells, sensor frame
  double voxel = 0.2;
  std::vector<double> crop_box;
  // Why no cells were learnt (empty when they were, or when learning was off).
  std::string note;

  bool contains(const Eigen::Vector3f& p) const;
  bool empty() const { return cells.empty() && crop_box.empty(); }
};

// Learns the mask from sensor-frame scans: the cells within max_range occupied in at least
// min_share of them. If those cells are most of what lies within max_range, the sensor stood
// still (a parked car, a tripod) and nothing tells the platform from the world: no cells are
// learnt, and `note` says so.
PlatformMask learn_platform_mask(const std::vector<Eigen::Matrix3Xf>& scans,
                                 const PlatformMaskConfig& config);

// Indices of the points outside the mask (sensor frame).
std::vector<std::int32_t> unmasked_points(const Eigen::Matrix3Xf& points, const PlatformMask& mask);

}  // namespace cleanmap
