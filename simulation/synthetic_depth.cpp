#include "simulation/synthetic_depth.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "io/depth_sequence.hpp"
#include "io/error.hpp"
#include "io/label_file.hpp"
#include "io/pose_file.hpp"
#include "simulation/ray_box.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

TableBox box(Eigen::Vector3d lo, Eigen::Vector3d hi, Eigen::Vector3d v = Eigen::Vector3d::Zero()) {
  return {lo, hi, v};
}

}  // namespace

TableScene make_table_scene(double push_speed) {
  TableScene s;
  auto& b = s.boxes;
  b.push_back(box({-3, -3, -0.1}, {3, 3, 0}));              // floor
  b.push_back(box({1.2, -3, 0}, {1.3, 3, 2.2}));            // the wall behind the table
  b.push_back(box({-0.6, -0.4, 0.72}, {0.6, 0.4, 0.75}));   // table top
  for (double x : {-0.55, 0.5}) {
    for (double y : {-0.35, 0.3}) b.push_back(box({x, y, 0}, {x + 0.05, y + 0.05, 0.72}));  // legs
  }
  b.push_back(box({0.2, 0.1, 0.75}, {0.4, 0.3, 0.8}));      // a book
  b.push_back(box({-0.35, 0.15, 0.75}, {-0.27, 0.23, 0.85}));  // a mug
  b.push_back(box({0.3, -0.3, 0.75}, {0.45, -0.2, 1.0}));   // a cereal box
  const Eigen::Vector3d v(push_speed, 0, 0);
  b.push_back(box({-0.25, -0.06, 0.75}, {-0.13, 0.06, 0.85}, v));  // the pushed object
  b.push_back(box({-0.35, -0.05, 0.75}, {-0.26, 0.05, 0.93}, v));  // the hand pushing it
  return s;
}

DepthIntrinsics synthetic_camera() {
  DepthIntrinsics k;
  k.fx = k.fy = 160.0 / std::tan(30.0 * M_PI / 180.0);
  k.cx = 159.5;
  k.cy = 119.5;
  k.depth_scale = 1000.0;
  k.min_depth = 0.2;
  k.max_depth = 2.5;
  return k;
}

Eigen::Isometry3d depth_camera_pose(const TableScene& s, double t) {
  const double theta = M_PI + 0.5 * s.arc_deg * M_PI / 180.0 * std::sin(M_PI * t / s.sweep_s);
  const Eigen::Vector3d p = s.table_centre + Eigen::Vector3d(s.arc_radius * std::cos(theta), s.arc_radius * std::sin(theta),
                                                             s.height - s.table_centre.z());
  const Eigen::Vector3d z = (s.table_centre - p).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = p;
  return pose;
}

DepthFrame render_depth(const TableScene& s, const DepthIntrinsics& k, double t, std::uint64_t seed) {
  DepthFrame f;
  f.stamp = t;
  f.pose = depth_camera_pose(s, t);
  const int w = static_cast<int>(2 * k.cx + 1), h = static_cast<int>(2 * k.cy + 1);
  f.depth = {w, h, std::vector<std::uint16_t>(static_cast<std::size_t>(w) * h, 0)};
  f.labels.assign(f.depth.pixels.size(), kLabelUnscored);
  std::mt19937_64 rng(seed * 1000003 + static_cast<std::uint64_t>(std::llround(t * 1000)));
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Vector3d o = f.pose.translation();
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      // Unnormalised, so the distance along it is the depth (the optical-axis coordinate).
      const Eigen::Vector3d dir = f.pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      double best = std::numeric_limits<double>::infinity();
      bool moving = false;
      for (const auto& b : s.boxes) {
        const Eigen::Vector3d shift = b.velocity * t;
        const double d = ray_box(o, dir, b.min + shift, b.max + shift);
        if (d < best) {
          best = d;
          moving = b.moving();
        }
      }
      if (!(best >= k.min_depth && best <= k.max_depth)) continue;
      const double z = best + 0.001 * best * best * noise(rng);  // ~1 mm at 1 m, growing with z^2
      const auto raw = static_cast<long>(std::lround(z * k.depth_scale));
      if (raw <= 0 || raw > 65535) continue;
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      f.depth.pixels[i] = static_cast<std::uint16_t>(raw);
      f.labels[i] = moving ? kLabelMoving : kLabelStatic;
    }
  }
  return f;
}

void write_table_sequence(const fs::path& folder, const TableScene& scene, int frames, double rate_hz,
                          std::uint64_t seed) {
  fs::create_directories(folder / "depth");
  fs::create_directories(folder / "labels");
  const DepthIntrinsics k = synthetic_camera();
  write_depth_intrinsics(folder / "camera.yaml", k);
  std::vector<DepthFrameEntry> list;
  std::vector<StampedPose> poses;
  const double t0 = 100.0;  // stamps as a camera driver gives them: seconds since some epoch
  for (int i = 0; i < frames; ++i) {
    const double t = i / rate_hz;
    const DepthFrame f = render_depth(scene, k, t, seed);
    char name[32];
    std::snprintf(name, sizeof(name), "%.6f", t0 + t);
    write_png16(folder / "depth" / (std::string(name) + ".png"), f.depth);
    write_labels(folder / "labels" / (std::string(name) + ".label"), f.labels);
    list.push_back({t0 + t, "depth/" + std::string(name) + ".png"});
    poses.push_back({t0 + t, f.pose});
  }
  write_depth_list(folder / "depth.txt", list);
  write_tum_poses(folder / "groundtruth.txt", poses);
}

}  // namespace cleanmap
