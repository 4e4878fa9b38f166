// Rays cast from where the sensor was when it fired: a sweep's origin moves with the sensor.
#include <gtest/gtest.h>

#include <vector>

#include "mapping/sweep_origin.hpp"
#include "mapping/visibility_map.hpp"
#include "tests/mapping/cloud_of.hpp"

namespace cleanmap {
namespace {

using test::cloud;

StampedPose at(double t, const Eigen::Vector3d& p) {
  StampedPose s;
  s.stamp = t;
  s.pose.translation() = p;
  return s;
}

TEST(SweepOrigin, IsWhereTheSensorWasAtTheStampMovingAtItsNeighboursVelocity) {
  // Odometry's poses sit mid-sweep (0.05 s after each stamp 0.1 k), the sensor at 5 m/s along x
  // and 1 m/s along y: the start is pose k less 0.05 s of travel, exactly.
  std::vector<StampedPose> poses;
  for (int k = 0; k < 4; ++k) poses.push_back(at(0.1 * k + 0.05, {5.0 * (0.1 * k + 0.05), 1.0 * (0.1 * k + 0.05), 1.8}));
  for (std::size_t i = 0; i < poses.size(); ++i) {  // central inside, one-sided at both ends
    const SweepOrigin s = sweep_origin(poses, i, 0.1 * static_cast<double>(i));
    EXPECT_NEAR((s.velocity - Eigen::Vector3d(5, 1, 0)).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR((s.start - Eigen::Vector3d(0.5 * static_cast<double>(i), 0.1 * static_cast<double>(i), 1.8)).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR((s.at(0.1) - s.start - Eigen::Vector3d(0.5, 0.1, 0)).norm(), 0.0, 1e-12);
  }
}

TEST(SweepOrigin, StandsStillWithoutTwoPosesApartInTime) {
  const Eigen::Vector3d p(1, 2, 3);
  for (const auto& poses : {std::vector<StampedPose>{at(0.0, p)},
                            std::vector<StampedPose>{at(0.0, p), at(0.0, p + Eigen::Vector3d(1, 0, 0))},
                            std::vector<StampedPose>{at(std::nan(""), p), at(std::nan(""), p + Eigen::Vector3d(1, 0, 0))}}) {
    const SweepOrigin s = sweep_origin(poses, 0, 0.0);
    EXPECT_EQ(s.velocity, Eigen::Vector3d::Zero());
    EXPECT_EQ(s.start, p);
  }
  EXPECT_THROW(sweep_origin({at(0.0, p)}, 1, 0.0), std::out_of_range);
}

// A post: hits filling the cell [4.0, 4.2) x [1.0, 1.2) x [1.0, 1.2) (spread along every axis:
// any ray through the cell goes through them).
Eigen::Matrix3Xf post() {
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      for (int k = 0; k < 10; ++k) p.emplace_back(4.01f + 0.02f * i, 1.01f + 0.02f * j, 1.01f + 0.02f * k);
    }
  }
  return cloud(p);
}

TEST(VisibilityMap, ARayIsCastFromWhereTheSensorWasWhenItFired) {
  // The sensor starts the sweep at (0, 0, 1.1) and moves at 5 m/s towards -y; it hits a wall at
  // (8.1, 2.2) at t = 0.1 s, from (0, -0.5). That ray passes x = 4.1 at y = 0.87, 13 cm
  // beside the post; the same ray drawn from the sweep's start passes at y = 1.11, through it.
  const Eigen::Vector3f post_cell(4.1f, 1.1f, 1.1f);
  const Eigen::Matrix3Xf wall = cloud({{8.1f, 2.2f, 1.1f}});
  const SweepOrigin sensor{{0, 0, 1.1}, {0, -5, 0}};
  for (const bool timed : {true, false}) {
    VisibilityMap map{VisibilityConfig{}};
    map.add_hits(post());
    map.add_hits(wall);
    map.fit_surfaces();
    map.count(timed ? map.cast(wall, Eigen::VectorXf::Constant(1, 0.1f), sensor) : map.cast(wall, sensor.start));
    EXPECT_EQ(map.counts(post_cell).through, timed ? 0 : 1) << timed;
  }
}

TEST(VisibilityMap, ASweepsRaysAreCastFromOnePlaceWhenTheSensorStandsOrHasNoTimes) {
  // Rays at every time of a sweep, standing still or without times, count as from one origin.
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < 40; ++i) p.emplace_back(8.1f, -1.0f + 0.1f * i, 1.1f);
  const Eigen::Matrix3Xf wall = cloud(p);
  Eigen::VectorXf times(wall.cols());
  for (Eigen::Index i = 0; i < times.size(); ++i) times[i] = 0.0025f * static_cast<float>(i);
  const Eigen::Vector3d origin(0, 0, 1.1);
  std::vector<std::uint16_t> through;
  for (int way = 0; way < 3; ++way) {
    VisibilityMap map{VisibilityConfig{}};
    map.add_hits(post());
    map.add_hits(wall);
    map.fit_surfaces();
    if (way == 0) map.count(map.cast(wall, origin));
    if (way == 1) map.count(map.cast(wall, times, SweepOrigin{origin}));
    if (way == 2) map.count(map.cast(wall, Eigen::VectorXf(), SweepOrigin{origin, Eigen::Vector3d(0, -5, 0)}));
    through.push_back(map.counts(Eigen::Vector3f(4.1f, 1.1f, 1.1f)).through);
  }
  EXPECT_EQ(through, (std::vector<std::uint16_t>{1, 1, 1}));
}

}  // namespace
}  // namespace cleanmap
