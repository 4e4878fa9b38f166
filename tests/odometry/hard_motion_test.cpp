// The failure class of the campus walk (issue 13): scans 0.5 s apart from a sensor that
// accelerates, turns on the spot and stops, and scans with half the view blocked. The
// constant-velocity prediction is then wrong by up to a whole step's motion.
#include <cstdio>
#include <functional>

#include "simulation/synthetic_lidar.hpp"
#include "odometry/lidar_odometry.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

struct Tracking {
  double max_step_error = 0.0;      // m, worst relative pose error per step
  double max_step_rotation = 0.0;   // deg
  double mean_step_error = 0.0;     // m
  double final_error = 0.0;         // m, position after the last scan (first pose aligned)
  int recoveries = 0;
  int degenerate = 0;
};

// A walk with the accelerations of a brisk walker or a small robot (velocity ramps, never
// jumps): still 1 s; 2 m/s^2 to 4 m/s; brakes at 4 m/s^2 to a stop at 4.5 s; turns 180 deg on
// the spot at up to 60 deg/s (ramping in 0.5 s; 30 deg between scans 0.5 s apart, like the
// fastest turns of the campus walk); then drives off at 3 m/s^2 to 3 m/s the way it came.
std::vector<PathKey> walk_turn_stop() {
  auto speed = [](double t) {
    if (t < 1.0) return 0.0;
    if (t < 3.0) return 2.0 * (t - 1.0);
    if (t < 3.5) return 4.0;
    if (t < 4.5) return 4.0 - 4.0 * (t - 3.5);
    if (t < 9.0) return 0.0;
    return std::min(3.0, 3.0 * (t - 9.0));
  };
  auto turn_rate = [](double t) {  // rad/s
    const double top = M_PI / 3;
    if (t < 5.0 || t > 8.5) return 0.0;
    if (t < 5.5) return top * (t - 5.0) / 0.5;
    if (t < 8.0) return top;
    return top * (8.5 - t) / 0.5;
  };
  std::vector<PathKey> keys{{0.0, 0, 0, 0}};
  PathKey k = keys.back();
  const double dt = 0.001;
  for (int i = 1; i <= 12000; ++i) {
    const double t = (i - 0.5) * dt;
    k.x += speed(t) * std::cos(k.yaw) * dt;
    k.y += speed(t) * std::sin(k.yaw) * dt;
    k.yaw += turn_rate(t) * dt;
    k.t = i * dt;
    if (i % 20 == 0) keys.push_back(k);
  }
  return keys;
}

// Scans every `stride` sweeps (5 at 10 Hz: 0.5 s apart); `edit` may cut a scan.
Tracking track(const SyntheticWorld& world, int scans, int stride,
               const std::function<void(int, Scan&)>& edit = {}) {
  LidarModel lidar;
  lidar.beams = 64;
  lidar.columns = 1024;
  LidarOdometry odom(OdometryConfig{});
  Tracking out;
  Eigen::Isometry3d first = Eigen::Isometry3d::Identity(), prev_truth = first, prev_est = first;
  for (int i = 0; i < scans; ++i) {
    auto s = simulate_scan(world, lidar, static_cast<std::size_t>(i * stride), 7);
    if (edit) edit(i, s.scan);
    const auto step = odom.register_scan(s.scan);
    out.recoveries += step.recovered;
    out.degenerate += step.degenerate;
    const Eigen::Isometry3d at_ref = sensor_pose(world, s.scan.stamp + step.reference_offset);
    if (i == 0) first = at_ref;
    const Eigen::Isometry3d truth = first.inverse() * at_ref;
    if (i > 0) {
      const Eigen::Isometry3d err = (prev_truth.inverse() * truth).inverse() * (prev_est.inverse() * step.pose);
      const double rot = Eigen::AngleAxisd(err.rotation()).angle() * 180 / M_PI;
      out.max_step_error = std::max(out.max_step_error, err.translation().norm());
      out.max_step_rotation = std::max(out.max_step_rotation, rot);
      out.mean_step_error += err.translation().norm() / (scans - 1);
    }
    out.final_error = (truth.translation() - step.pose.translation()).norm();
    prev_truth = truth;
    prev_est = step.pose;
  }
  std::printf("max step %.3f m %.2f deg, mean %.3f m, final %.3f m, recoveries %d\n", out.max_step_error,
              out.max_step_rotation, out.mean_step_error, out.final_error, out.recoveries);
  return out;
}

// The street alone is a corridor: walls and road say nothing about motion along it, and only
// sparse poles and car ends do; a sensor starting from rest there is a degenerate case that the
// conditioning check flags, not what these tests are about. So the walk happens on a square:
// the street plus benches and trees beside the path, as around the campus walk.
SyntheticWorld walker_world() {
  SyntheticWorld world = make_street_world(5);
  using Shape = SceneObject::Shape;
  for (int i = 0; i < 12; ++i) {
    const double x = -8.0 + 2.5 * i, side = i % 2 == 0 ? 1.0 : -1.0;
    world.objects.push_back({Shape::kBox, {x, side * 3.8}, {0, 0}, 0.3 * i, {1.6, 0.6, 0.9}, 70.f});
    world.objects.push_back({Shape::kCylinder, {x + 1.2, -side * 4.4}, {0, 0}, 0.0, {0.3, 0, 4.0}, 90.f});
  }
  world.path = walk_turn_stop();
  return world;
}

TEST(HardMotion, AcceleratesTurnsOnTheSpotAndStopsWithScansHalfASecondApart) {
  const Tracking t = track(walker_world(), 24, 5);
  EXPECT_EQ(t.degenerate, 0);
  // Tracking means the map held: 0.1 m after 14 m, a 180 deg turn and two stops (the old
  // odometry ended 22 m off, steps wrong by 3.5 m / 27 deg). Single steps may err by up to
  // 0.25 m where the turn rate changes between scans: a 60 deg/s turn spreads 6 deg over one
  // sweep, and undistortion assumes the rate of the last step.
  EXPECT_LT(t.max_step_error, 0.25);
  EXPECT_LT(t.max_step_rotation, 0.5);
  EXPECT_LT(t.mean_step_error, 0.05);
  EXPECT_LT(t.final_error, 0.1);
}

TEST(HardMotion, TheSameWalkAtTenHertz) {
  const Tracking t = track(walker_world(), 120, 1);
  EXPECT_EQ(t.degenerate, 0);
  // At 10 Hz the prediction is close: steps within 0.15 m / 0.5 deg (transitions of the turn
  // rate), 2 cm on average, 0.1 m at the end (old: 0.40 m / 6 deg per step, 0.86 m at the end).
  EXPECT_LT(t.max_step_error, 0.15);
  EXPECT_LT(t.max_step_rotation, 0.5);
  EXPECT_LT(t.mean_step_error, 0.02);
  EXPECT_LT(t.final_error, 0.1);
}

TEST(HardMotion, HalfTheViewBlocked) {
  // Scans 8-11 (the stop and the start of the turn) see only the half in front (sensor x > 0):
  // a wall or a passing bus beside the sensor.
  const Tracking t = track(walker_world(), 24, 5, [](int i, Scan& s) {
    if (i < 8 || i > 11) return;
    std::vector<std::int32_t> keep;
    for (Eigen::Index k = 0; k < s.points.cols(); ++k) {
      if (s.points(0, k) > 0) keep.push_back(static_cast<std::int32_t>(k));
    }
    s = select_points(s, keep);
  });
  EXPECT_EQ(t.degenerate, 0);
  // Half blind through a stop and the start of a turn: steps within 0.5 m / 1.5 deg, and the
  // map holds (0.1 m at the end; old: 14 m, steps wrong by 2 m / 29 deg).
  EXPECT_LT(t.max_step_error, 0.5);
  EXPECT_LT(t.max_step_rotation, 1.5);
  EXPECT_LT(t.mean_step_error, 0.1);
  EXPECT_LT(t.final_error, 0.1);
}

}  // namespace
}  // namespace cleanmap
