#include "simulation/synthetic_lidar.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "io/label_file.hpp"
#include "simulation/ray_box.hpp"

namespace cleanmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Ray (o + s d) against an object at time t; returns s of the first hit beyond 0 or inf.
double intersect(const SceneObject& obj, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                 double t) {
  const Eigen::Vector2d c = obj.centre_at(t);
  if (obj.shape == SceneObject::Shape::kCylinder) {
    const double r = obj.size.x();
    const Eigen::Vector2d oc = o.head<2>() - c;
    const double a = d.head<2>().squaredNorm();
    if (a < 1e-12) return kInf;
    const double b = oc.dot(d.head<2>());
    const double disc = b * b - a * (oc.squaredNorm() - r * r);
    if (disc < 0) return kInf;
    const double s = (-b - std::sqrt(disc)) / a;
    if (s <= 0) return kInf;
    const double z = o.z() + s * d.z();
    return (z >= 0 && z <= obj.size.z()) ? s : kInf;
  }
  // Slab test in the box frame (yaw only).
  const double cy = std::cos(obj.yaw), sy = std::sin(obj.yaw);
  const Eigen::Vector2d rel = o.head<2>() - c;
  const Eigen::Vector3d ob(cy * rel.x() + sy * rel.y(), -sy * rel.x() + cy * rel.y(), o.z());
  const Eigen::Vector3d db(cy * d.x() + sy * d.y(), -sy * d.x() + cy * d.y(), d.z());
  const Eigen::Vector3d lo(-obj.size.x() / 2, -obj.size.y() / 2, 0.0);
  const Eigen::Vector3d hi(obj.size.x() / 2, obj.size.y() / 2, obj.size.z());
  return ray_box(ob, db, lo, hi);
}

double bounding_radius(const SceneObject& obj) {
  return obj.shape == SceneObject::Shape::kCylinder ? obj.size.x()
                                                    : 0.5 * obj.size.head<2>().norm();
}

}  // namespace

SyntheticWorld make_street_world(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SyntheticWorld w;
  std::uint32_t next_id = 1;
  auto add = [&](SceneObject o) {
    o.id = next_id++;
    w.objects.push_back(o);
  };
  using Shape = SceneObject::Shape;
  // Buildings on both sides, with gaps (so the scene is not a perfect corridor).
  for (int side : {-1, 1}) {
    for (double x = -60; x < 200; x += 24) {
      add({Shape::kBox, {x + 10, side * 17.0}, {0.0, 0.0}, 0.0, {20.0, 6.0, 8.0 + 8.0 * u(rng)}, 80.f});
    }
  }
  // Poles along both kerbs.
  for (int side : {-1, 1}) {
    for (double x = -50; x < 200; x += 12) {
      add({Shape::kCylinder, {x + 4 * u(rng), side * 8.5}, {0.0, 0.0}, 0.0, {0.15, 0, 6.0}, 120.f});
    }
  }
  // Crossings: pedestrians cross the road there, so no car is parked across them.
  std::vector<double> crossings;
  for (int k = 0; k < 3; ++k) crossings.push_back(12.0 + 10.0 * k + 3 * u(rng));
  // Parked cars.
  for (int side : {-1, 1}) {
    for (double x = -50; x < 200; x += 9) {
      const bool skip = u(rng) < 0.35;
      bool at_crossing = false;
      for (double c : crossings) at_crossing = at_crossing || std::abs(x - c) < 4.0;
      if (skip || at_crossing) continue;
      add({Shape::kBox, {x, side * 6.2}, {0.0, 0.0}, 0.02 * (u(rng) - 0.5), {4.4, 1.8, 1.5}, 60.f});
    }
  }
  // Moving cars: oncoming lane (y = -2.6) and same direction (y = +2.6), 6-10 m/s.
  for (int k = 0; k < 4; ++k) {
    add({Shape::kBox, {15.0 + 25.0 * k + 5 * u(rng), -2.6}, {-(6.0 + 4 * u(rng)), 0.0}, M_PI,
         {4.4, 1.8, 1.5}, 60.f});
    add({Shape::kBox, {8.0 + 20.0 * k + 5 * u(rng), 2.6}, {6.0 + 3 * u(rng), 0.0}, 0.0,
         {4.4, 1.8, 1.5}, 60.f});
  }
  // Pedestrians: walking along the pavements and crossing the road.
  for (int k = 0; k < 6; ++k) {
    const double side = (k % 2) ? 1.0 : -1.0;
    add({Shape::kCylinder, {5.0 + 8.0 * k + 3 * u(rng), side * 10.5},
         {(u(rng) < 0.5 ? -1 : 1) * (1.0 + 0.6 * u(rng)), 0.0}, 0.0, {0.3, 0, 1.75}, 40.f});
  }
  for (double c : crossings) {
    add({Shape::kCylinder, {c, -9.0 + 2 * u(rng)}, {0.0, 1.0 + 0.5 * u(rng)}, 0.0,
         {0.3, 0, 1.75}, 40.f});
  }
  return w;
}

namespace {

Eigen::Isometry3d pose_on_path(const std::vector<PathKey>& path, double t, double height) {
  const auto after = std::lower_bound(path.begin(), path.end(), t,
                                      [](const PathKey& key, double time) { return key.t < time; });
  PathKey at = after == path.end() ? path.back() : *after;
  if (after != path.begin() && after != path.end()) {
    const PathKey& a = *(after - 1);
    const double f = (t - a.t) / (after->t - a.t);
    at = {t, a.x + f * (after->x - a.x), a.y + f * (after->y - a.y), a.yaw + f * (after->yaw - a.yaw)};
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(at.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(at.x, at.y, height);
  return pose;
}

}  // namespace

Eigen::Isometry3d sensor_pose(const SyntheticWorld& w, double t) {
  if (!w.path.empty()) return pose_on_path(w.path, t, w.sensor_height);
  const double k = 2 * M_PI / w.sway_period;
  const double x = w.speed * t;
  const double y = w.sway_amplitude * std::sin(k * t);
  const double yaw = std::atan2(w.sway_amplitude * k * std::cos(k * t), w.speed);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, w.sensor_height);
  return pose;
}

namespace {

// Every ray of one sweep (column-major, `rows` per column): its range (NaN: no return) and
// the object it hit (nullptr: the ground).
struct SweepHits {
  std::vector<double> range;
  std::vector<const SceneObject*> hit;
};

// Objects that can be seen at all in the sweep from `stamp` (within range, wherever they move
// to).
std::vector<const SceneObject*> objects_in_reach(const SyntheticWorld& world, const LidarModel& lidar,
                                                 double stamp, double period) {
  const Eigen::Vector3d sensor_mid = sensor_pose(world, stamp + period / 2).translation();
  std::vector<const SceneObject*> near;
  for (const auto& obj : world.objects) {
    const Eigen::Vector2d c = obj.centre_at(stamp + period / 2);
    if ((c - sensor_mid.head<2>()).norm() - bounding_radius(obj) - obj.velocity.norm() * period <
        lidar.max_range) {
      near.push_back(&obj);
    }
  }
  return near;
}

double elevation(const LidarModel& lidar, int r) {
  const double up = lidar.fov_up_deg * M_PI / 180, down = lidar.fov_down_deg * M_PI / 180;
  return lidar.beams == 1 ? 0.0 : down + (up - down) * r / (lidar.beams - 1);
}

SweepHits cast_sweep(const SyntheticWorld& world, const LidarModel& lidar, double stamp, double period) {
  const int rows = lidar.beams, cols = lidar.columns;
  SweepHits out;
  out.range.assign(static_cast<std::size_t>(rows) * cols, std::nan(""));
  out.hit.assign(out.range.size(), nullptr);
  const auto near = objects_in_reach(world, lidar, stamp, period);
  tbb::parallel_for(0, cols, [&](int c) {
    const double t = stamp + period * c / cols;
    const Eigen::Isometry3d pose = sensor_pose(world, t);
    const double az = 2 * M_PI * c / cols;
    const Eigen::Vector3d o = pose.translation();
    // Cull by the column's vertical plane: only objects whose footprint circle it crosses.
    const Eigen::Vector3d horizontal = pose.linear() * Eigen::Vector3d(std::cos(az), std::sin(az), 0);
    std::vector<const SceneObject*> candidates;
    for (const auto* obj : near) {
      const Eigen::Vector2d rel = obj->centre_at(t) - o.head<2>();
      const double along = rel.dot(horizontal.head<2>());
      const double across = std::abs(rel.x() * horizontal.y() - rel.y() * horizontal.x());
      const double r = bounding_radius(*obj);
      if (across <= r && along >= -r) candidates.push_back(obj);
    }
    for (int r = 0; r < rows; ++r) {
      const double el = elevation(lidar, r);
      const Eigen::Vector3d d_sensor(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                     std::sin(el));
      const Eigen::Vector3d d = pose.linear() * d_sensor;
      double best = d.z() < 0 ? -o.z() / d.z() : kInf;  // ground plane z = 0
      const SceneObject* best_obj = nullptr;
      for (const auto* obj : candidates) {
        const double s = intersect(*obj, o, d, t);
        if (s < best) {
          best = s;
          best_obj = obj;
        }
      }
      if (best >= lidar.min_range && best <= lidar.max_range) {
        const std::size_t k = static_cast<std::size_t>(c) * rows + r;
        out.range[k] = best;
        out.hit[k] = best_obj;
      }
    }
  });
  return out;
}

}  // namespace

SyntheticScan simulate_scan(const SyntheticWorld& world, const LidarModel& lidar,
                            std::size_t index, std::uint64_t seed) {
  const double period = 1.0 / lidar.rate_hz;
  const double stamp = static_cast<double>(index) * period;
  const int rows = lidar.beams, cols = lidar.columns;
  const SweepHits sweep = cast_sweep(world, lidar, stamp, period);

  // The returns, compacted in column order.
  SyntheticScan out;
  Scan& scan = out.scan;
  std::size_t n = 0;
  for (double r : sweep.range) n += std::isfinite(r) ? 1 : 0;
  scan.points.resize(3, static_cast<Eigen::Index>(n));
  scan.time.resize(static_cast<Eigen::Index>(n));
  scan.intensity.resize(static_cast<Eigen::Index>(n));
  out.labels.resize(n);
  // Noise drawn in a fixed order from a per-scan seed, so results do not depend on threads.
  std::mt19937_64 rng(seed * 1000003ULL + index);
  std::normal_distribution<double> noise(0.0, lidar.range_noise);
  Eigen::Index j = 0;
  for (int c = 0; c < cols; ++c) {
    const double az = 2 * M_PI * c / cols;
    for (int r = 0; r < rows; ++r) {
      const std::size_t k = static_cast<std::size_t>(c) * rows + r;
      if (!std::isfinite(sweep.range[k])) continue;
      const double el = elevation(lidar, r);
      const double rho = sweep.range[k] + (lidar.range_noise > 0 ? noise(rng) : 0.0);
      scan.points.col(j) = (rho * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                                  std::cos(el) * std::sin(az), std::sin(el)))
                               .cast<float>();
      scan.time[j] = static_cast<float>(period * c / cols);
      const SceneObject* obj = sweep.hit[k];
      scan.intensity[j] = obj ? obj->intensity : 30.0f;
      const std::uint32_t cls = (obj && obj->moving()) ? kLabelMoving : kLabelStatic;
      out.labels[static_cast<std::size_t>(j)] = cls | ((obj ? obj->id : 0u) << 16);
      ++j;
    }
  }
  scan.stamp = stamp;
  scan.pose = sensor_pose(world, stamp);
  scan.input_size = n;
  scan.name = scan_name(index);
  return out;
}

SyntheticSequence simulate_sequence(const SyntheticWorld& world, const LidarModel& lidar,
                                    std::size_t count, std::uint64_t seed) {
  SyntheticSequence out;
  for (std::size_t i = 0; i < count; ++i) {
    auto s = simulate_scan(world, lidar, i, seed);
    out.scans.push_back(std::move(s.scan));
    out.labels.push_back(std::move(s.labels));
  }
  return out;
}

}  // namespace cleanmap
