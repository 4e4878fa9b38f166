#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap {

// A spinning multi-beam lidar: beams fire column by column over one revolution, so every point
// has its own capture time and sensor pose (rolling shutter), as on a real sensor.
struct LidarModel {
  int beams = 64;
  int columns = 2048;
  double rate_hz = 10.0;
  double fov_up_deg = 22.5;  // Ouster OS1-64-like vertical field of view
  double fov_down_deg = -22.5;
  double min_range = 0.8;
  double max_range = 100.0;
  double range_noise = 0.01;  // metres, Gaussian, along the ray
};

// An upright box (cars, buildings) or vertical cylinder (poles, pedestrians) standing on z = 0,
// moving at a constant velocity (zero for static structure), optionally stopping on the way
// (a car at a light): still from `stop_at` for `stop_for` seconds, then on at the same velocity.
// A moving object is labelled moving in every scan, stopped or not: it is no part of the
// static world.
struct SceneObject {
  enum class Shape { kBox, kCylinder } shape = Shape::kBox;
  Eigen::Vector2d centre{0, 0};    // at time 0
  Eigen::Vector2d velocity{0, 0};  // m/s in the world frame
  double yaw = 0.0;                // boxes only
  Eigen::Vector3d size{1, 1, 1};   // box: length, width, height; cylinder: radius, -, height
  float intensity = 50.0f;
  std::uint32_t id = 0;  // instance id, written in the upper 16 bits of the labels
  double stop_at = std::numeric_limits<double>::infinity();  // s
  double stop_for = 0.0;                                      // s
  bool moving() const { return velocity.squaredNorm() > 0.0; }
  Eigen::Vector2d centre_at(double t) const {
    const double moved = t < stop_at ? t : t < stop_at + stop_for ? stop_at : t - stop_for;
    return centre + velocity * moved;
  }
};

// A point of a keyframed sensor path: planar position and heading at time t.
struct PathKey {
  double t = 0.0;  // s
  double x = 0.0, y = 0.0;
  double yaw = 0.0;  // rad, unwrapped (2 pi + 0.1 is a full turn more than 0.1)
};

struct SyntheticWorld {
  std::vector<SceneObject> objects;
  // Sensor path: forward at `speed` along x with a gentle lateral sway (yaw follows the path),
  // unless `path` is given: then position and yaw are interpolated linearly between its keys
  // (sorted by time; held before the first and after the last). Velocity is constant between
  // two keys, so dense keys trace any speed profile.
  std::vector<PathKey> path;
  double speed = 5.0;
  double sway_amplitude = 0.5;
  double sway_period = 8.0;
  double sensor_height = 1.8;
};

struct SyntheticConfig {
  LidarModel lidar;
  int scans = 30;
  std::uint64_t seed = 1;
};

struct SyntheticScan {
  Scan scan;  // sensor frame, distorted by the motion during the sweep; pose = pose at stamp
  std::vector<std::uint32_t> labels;  // MOS labels: 251 moving / 9 static, instance id above
};

// A street: buildings, poles, parked cars, cars in both lanes and pedestrians crossing and
// walking, placed from the seed.
SyntheticWorld make_street_world(std::uint64_t seed);

// Sensor -> world at time t (seconds from the start of the sequence).
Eigen::Isometry3d sensor_pose(const SyntheticWorld& world, double t);

// Scan `index` of the sequence: stamp = index / rate (start of the sweep), per-point times in
// [0, 1/rate). Deterministic for (world, model, index, seed).
SyntheticScan simulate_scan(const SyntheticWorld& world, const LidarModel& lidar,
                            std::size_t index, std::uint64_t seed);

// Scans 0 .. count-1 of that sequence, their labels alongside.
struct SyntheticSequence {
  std::vector<Scan> scans;
  std::vector<std::vector<std::uint32_t>> labels;
};
SyntheticSequence simulate_sequence(const SyntheticWorld& world, const LidarModel& lidar,
                                    std::size_t count, std::uint64_t seed);

}  // namespace cleanmap
