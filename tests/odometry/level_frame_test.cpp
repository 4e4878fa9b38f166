// Levelling a depth camera's first frame on the plane it looks at.
#include <gtest/gtest.h>

#include <random>

#include "odometry/level_frame.hpp"
#include "odometry/lidar_odometry.hpp"

namespace cleanmap {
namespace {

// A camera 0.8 m above a floor, looking down 47 degrees (optical frame: z forward, y down).
struct TiltedCamera {
  Eigen::Matrix3d to_world =
      Eigen::AngleAxisd(-M_PI / 2 - 47.0 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Eigen::Vector3d position{0, 0, 0.8};
  Eigen::Vector3f seen(const Eigen::Vector3d& world) const {  // into the camera frame
    return (to_world.transpose() * (world - position)).cast<float>();
  }
  Eigen::Vector3d floor_up() const { return to_world.transpose() * Eigen::Vector3d::UnitZ(); }  // in the camera frame
};

TEST(LevelFrame, TheDominantPlaneBecomesHorizontalWithUpTowardsTheCamera) {
  // The camera sees the floor (70% of its points) and a box (30%) off it.
  const TiltedCamera camera;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3Xf pts(3, 1000);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d w = i < 700 ? Eigen::Vector3d(u(rng), 1.0 + 0.5 * u(rng), 0.0)
                                      : Eigen::Vector3d(0.2 * u(rng), 1.0 + 0.2 * u(rng), 0.1 + 0.1 * (u(rng) + 1));
    pts.col(i) = camera.seen(w);
  }
  const auto r = level_rotation(pts);
  ASSERT_TRUE(r);
  // The floor's normal, seen from the camera, must come out as +z: exactly the camera's tilt.
  const Eigen::Vector3d floor_up_in_camera = camera.floor_up();
  EXPECT_TRUE((*r * floor_up_in_camera).isApprox(Eigen::Vector3d::UnitZ(), 1e-5));
  // A wall facing the camera, bigger than the floor it sees, is not the support.
  Eigen::Matrix3Xf room(3, 1000);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d w = i < 400 ? Eigen::Vector3d(u(rng), 1.0 + 0.5 * u(rng), 0.0)
                                      : Eigen::Vector3d(u(rng), 2.0, 1.0 + 0.8 * u(rng));  // above 0.2 m
    room.col(i) = camera.seen(w);
  }
  const auto in_room = level_rotation(room);
  ASSERT_TRUE(in_room);
  EXPECT_TRUE((*in_room * floor_up_in_camera).isApprox(Eigen::Vector3d::UnitZ(), 1e-5));
  // Nothing plane-like: no answer, and the frame is kept.
  Eigen::Matrix3Xf cloud(3, 500);
  for (int i = 0; i < 500; ++i) cloud.col(i) = Eigen::Vector3f(u(rng), u(rng), u(rng));
  EXPECT_FALSE(level_rotation(cloud));
}

TEST(LevelFrame, TheOdometryBuildsItsMapInTheLevelledWorld) {
  // The camera of the test above, still, over a floor with a box: with level_first_scan the
  // odometry's first pose is the levelling rotation, and the next scan registers in that frame.
  const TiltedCamera camera;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  Scan scan;
  scan.points.resize(3, 6000);
  for (int i = 0; i < 6000; ++i) {
    const Eigen::Vector3d w = i < 4200 ? Eigen::Vector3d(u(rng), 1.0 + 0.5 * u(rng), 0.0)
                              : i < 5000 ? Eigen::Vector3d(0.2 * u(rng), 1.0 + 0.2 * u(rng), 0.1 + 0.1 * (u(rng) + 1))
                                         : Eigen::Vector3d(u(rng), 1.6, 0.05 + 0.6 * (u(rng) + 1));  // a wall behind
    scan.points.col(i) = camera.seen(w);
  }
  OdometryConfig cfg;
  cfg.min_range = 0.2;
  cfg.max_range = 3.0;
  cfg.map_voxel_size = 0.02;
  cfg.initial_threshold = 0.1;
  cfg.deskew = false;
  cfg.level_first_scan = true;
  LidarOdometry odom(cfg);
  const Eigen::Vector3d floor_up_in_camera = camera.floor_up();
  const auto first = odom.register_scan(scan);
  EXPECT_TRUE(first.note.empty()) << first.note;
  EXPECT_TRUE((first.pose.linear() * floor_up_in_camera).isApprox(Eigen::Vector3d::UnitZ(), 1e-5));
  EXPECT_LT(first.pose.translation().norm(), 1e-12);
  scan.stamp = 1.0 / 30;
  const auto second = odom.register_scan(scan);
  EXPECT_FALSE(second.degenerate) << second.note;
  EXPECT_LT((second.pose.linear() * floor_up_in_camera - Eigen::Vector3d::UnitZ()).norm(), 1e-3);
  EXPECT_LT(second.pose.translation().norm(), 1e-3);
  // Without a plane the frame is kept, and the step says why.
  LidarOdometry plain(cfg);
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) scan.points.col(i) = Eigen::Vector3f(u(rng), u(rng), u(rng) + 1.5f);
  const auto kept = plain.register_scan(scan);
  EXPECT_NE(kept.note.find("no dominant plane"), std::string::npos) << kept.note;
  EXPECT_TRUE(kept.pose.isApprox(Eigen::Isometry3d::Identity()));
}

}  // namespace
}  // namespace cleanmap
