#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/depth_image.hpp"

namespace cleanmap {

// The paper's second experiment, simulated: a depth camera on a robot arm sweeping over a table
// while a hand-sized box pushes an object across it. Everything is an axis-aligned box (floor,
// table top, objects, the hand); the camera is a pinhole with depth noise that grows with the
// square of the depth (structured light and active stereo: about 1 mm at 1 m) and quantised
// to the camera's depth units.
struct TableBox {
  Eigen::Vector3d min, max;  // at time 0, world frame (z up, floor at 0)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s
  bool moving() const { return velocity.squaredNorm() > 0; }
};

struct TableScene {
  std::vector<TableBox> boxes;
  // Camera: on an arc of `arc_radius` around the table centre, `height` above the floor,
  // swinging from -arc_deg/2 to +arc_deg/2 over `sweep_s` and back, always looking at the
  // table's centre.
  Eigen::Vector3d table_centre{0, 0, 0.75};
  double arc_radius = 0.55, height = 1.35, arc_deg = 50.0, sweep_s = 4.0;
};

// Floor, a 1.2 x 0.8 m table, a few static objects on it, and a 12 cm object pushed at
// `push_speed` m/s by the hand behind it.
TableScene make_table_scene(double push_speed = 0.15);

DepthIntrinsics synthetic_camera();  // 320 x 240, 60 x 47 degrees, 1 mm units, 0.2-2.5 m

// Camera optical frame (x right, y down, z forward) -> world at time t.
Eigen::Isometry3d depth_camera_pose(const TableScene& scene, double t);

struct DepthFrame {
  Image16 depth;
  std::vector<std::uint32_t> labels;  // per pixel: 251 moving, 9 static, 0 no depth
  Eigen::Isometry3d pose;
  double stamp = 0.0;
};

DepthFrame render_depth(const TableScene& scene, const DepthIntrinsics& camera, double t, std::uint64_t seed);

// Writes `frames` frames at `rate_hz` in the TUM RGB-D layout (depth/, depth.txt,
// groundtruth.txt, camera.yaml) plus labels/*.label for scoring.
void write_table_sequence(const std::filesystem::path& folder, const TableScene& scene, int frames, double rate_hz,
                          std::uint64_t seed);

}  // namespace cleanmap
