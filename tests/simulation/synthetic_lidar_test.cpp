#include "simulation/synthetic_lidar.hpp"

#include "io/label_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

LidarModel small_lidar() {
  LidarModel m;
  m.beams = 32;
  m.columns = 512;
  return m;
}

TEST(SyntheticLidar, DeterministicForASeed) {
  const auto world = make_street_world(3);
  const auto a = simulate_scan(world, small_lidar(), 4, 3);
  const auto b = simulate_scan(world, small_lidar(), 4, 3);
  EXPECT_TRUE(a.scan.points.isApprox(b.scan.points));
  EXPECT_EQ(a.labels, b.labels);
  const auto c = simulate_scan(world, small_lidar(), 4, 4);
  EXPECT_FALSE(a.scan.points.isApprox(c.scan.points));  // other noise
}

TEST(SyntheticLidar, RollingShutterTimesCoverOneSweep) {
  const auto world = make_street_world(1);
  const auto s = simulate_scan(world, small_lidar(), 2, 1);
  ASSERT_TRUE(s.scan.has_time());
  EXPECT_GE(s.scan.time.minCoeff(), 0.0f);
  EXPECT_LT(s.scan.time.maxCoeff(), 0.1f);
  EXPECT_GT(s.scan.time.maxCoeff(), 0.09f);
  EXPECT_DOUBLE_EQ(s.scan.stamp, 0.2);
  EXPECT_TRUE(s.scan.pose->isApprox(sensor_pose(world, 0.2)));
}

TEST(SyntheticLidar, GroundPointsLieOnTheGroundOnceEachIsPlacedWithItsOwnPose) {
  LidarModel m = small_lidar();
  m.range_noise = 0.0;
  const auto world = make_street_world(1);
  const auto s = simulate_scan(world, m, 5, 1);
  int ground = 0;
  double worst_exact = 0.0, worst_single_pose = 0.0;
  for (std::size_t i = 0; i < s.scan.size(); ++i) {
    if (instance_id(s.labels[i]) != 0) continue;  // 0 = ground
    ++ground;
    const Eigen::Vector3d p = s.scan.points.col(static_cast<Eigen::Index>(i)).cast<double>();
    const auto at_capture = sensor_pose(world, s.scan.stamp + s.scan.time[static_cast<Eigen::Index>(i)]);
    worst_exact = std::max(worst_exact, std::abs((at_capture * p).z()));
    worst_single_pose = std::max(worst_single_pose, std::abs((*s.scan.pose * p).x() - (at_capture * p).x()));
  }
  EXPECT_GT(ground, 1000);
  EXPECT_LT(worst_exact, 1e-4);
  // Placing every point with the sweep-start pose is off by up to speed x sweep time (0.5 m):
  // the distortion odometry has to undo.
  EXPECT_GT(worst_single_pose, 0.4);
}

TEST(SyntheticLidar, MovingObjectsAreLabelledMoving) {
  const auto world = make_street_world(1);
  const auto s = simulate_scan(world, small_lidar(), 0, 1);
  std::size_t moving = 0;
  for (auto l : s.labels) moving += is_moving_label(l);
  EXPECT_GT(moving, 100u);
  EXPECT_LT(moving, s.labels.size() / 4);
}

}  // namespace
}  // namespace cleanmap
