// Which boxes move, measured on the objects' own points: exact shifts recovered by the
// registration, and the two ways hand-drawn boxes mislead (a parked truck whose interpolated
// boxes creep, a braking truck whose boxes were copied) told right by the points.
#include "evaluation/object_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cleanmap {
namespace {

// The surfaces a lidar sees of a 5 x 2.4 x 2.6 m truck standing at `origin` (its rear-left
// bottom corner): its left side, its rear and its roof, sampled every `step` m starting
// `phase` m in (a scan of the same surface from another place samples it elsewhere).
Eigen::Matrix3Xf truck(const Eigen::Vector3d& origin, double step = 0.08, double phase = 0.0) {
  std::vector<Eigen::Vector3f> p;
  for (double u = phase; u < 5.0; u += step) {
    for (double v = phase; v < 2.6; v += step) p.push_back((origin + Eigen::Vector3d(u, 0, v)).cast<float>());
    for (double w = phase; w < 2.4; w += step) p.push_back((origin + Eigen::Vector3d(u, w, 2.6)).cast<float>());
  }
  for (double w = phase; w < 2.4; w += step) {
    for (double v = phase; v < 2.6; v += step) p.push_back((origin + Eigen::Vector3d(0, w, v)).cast<float>());
  }
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

// A road under it, every 5 cm over 10 x 6 m around `centre`, at height 0.
Eigen::Matrix3Xf road(const Eigen::Vector3d& centre) {
  std::vector<Eigen::Vector3f> p;
  for (double x = -5; x < 5; x += 0.05) {
    for (double y = -3; y < 3; y += 0.05) p.push_back((centre + Eigen::Vector3d(x, y, 0)).cast<float>());
  }
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

TEST(RegisterObject, RecoversAShiftExactlyFromAJitteredGuess) {
  const Eigen::Vector3d shift(0.7, -0.2, 0.0);
  const auto from = truck(Eigen::Vector3d(10, -4, 0));
  const auto to = truck(Eigen::Vector3d(10, -4, 0) + shift);
  // A hand-drawn box's jitter (0.2-0.5 m) in the guess.
  const auto s = register_object(from, to, shift + Eigen::Vector3d(0.3, -0.2, 0.1));  // height: ignored
  ASSERT_TRUE(s);
  EXPECT_LT((s->translation - shift).norm(), 1e-4);
  EXPECT_LT(s->residual, 1e-4);
}

TEST(RegisterObject, ASurfaceSampledElsewhereShiftsToWithinItsSampling) {
  const Eigen::Vector3d shift(-1.2, 0.3, 0.0);
  const auto from = truck(Eigen::Vector3d(10, -4, 0), 0.08, 0.0);
  const auto to = truck(Eigen::Vector3d(10, -4, 0) + shift, 0.08, 0.03);
  const auto s = register_object(from, to, shift + Eigen::Vector3d(-0.4, 0.0, 0.0));
  ASSERT_TRUE(s);
  EXPECT_LT((s->translation - shift).norm(), 0.02);
  EXPECT_LT(s->residual, 0.05);
  EXPECT_FALSE(register_object(Eigen::Matrix3Xf(3, 0), to, shift));
}

TEST(RegisterObject, ALoneWallSlidingAlongItselfIsAmbiguous) {
  // A 5 x 2.6 m wall (the truck's side alone) moved 0.5 m along itself and sampled elsewhere,
  // as another scan samples it: nothing fixes that motion, so the start from the boxes and the
  // start from standing end 0.5 m apart, both fitting.
  auto side_of = [](const Eigen::Matrix3Xf& t) {
    std::vector<Eigen::Index> side;
    for (Eigen::Index i = 0; i < t.cols(); ++i) {
      if (t(1, i) == -4.0f && t(2, i) < 2.6f) side.push_back(i);
    }
    return Eigen::Matrix3Xf(t(Eigen::all, side));
  };
  const Eigen::Matrix3Xf from = side_of(truck(Eigen::Vector3d(10, -4, 0)));
  const Eigen::Matrix3Xf to = side_of(truck(Eigen::Vector3d(10.5, -4, 0), 0.08, 0.03));
  const auto s = register_object(from, to, Eigen::Vector3d(0.5, 0, 0));
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->ambiguous);
  // With the rear and the roof the same shift is fixed.
  const auto whole = register_object(truck(Eigen::Vector3d(10, -4, 0)), truck(Eigen::Vector3d(10.5, -4, 0)),
                                     Eigen::Vector3d(0.5, 0, 0));
  ASSERT_TRUE(whole);
  EXPECT_FALSE(whole->ambiguous);
  EXPECT_LT((whole->translation - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-4);
}

// A log at 10 Hz of a sensor driving along x at 6 m/s past one truck: `truck_at(t)` is the
// truck's rear-left bottom corner in the world at time t, `box_at(i)` its hand-drawn box
// centre in the world at scan i. Returns the speeds the points give, and whether the centres
// (1 s line fit) and the points call it moving, scan by scan.
struct Verdicts {
  std::vector<double> speed;
  std::vector<bool> by_centres, by_points;
};

template <typename TruckAt, typename BoxAt>
Verdicts drive_past(int scans, TruckAt truck_at, BoxAt box_at, bool with_road = false, double ground_band = 0.25) {
  std::vector<std::vector<LabelBox>> boxes;
  std::vector<std::vector<Eigen::Matrix3Xf>> points;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<double> times;
  for (int i = 0; i < scans; ++i) {
    const double t = 0.1 * i;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(6.0 * t, 0, 1.8);
    Eigen::Matrix3Xf world = truck(truck_at(t), 0.08, 0.02 * (i % 4));
    if (with_road) {
      const Eigen::Matrix3Xf ground = road(box_at(i));
      Eigen::Matrix3Xf both(3, world.cols() + ground.cols());
      both << world, ground;
      world = both;
    }
    const Eigen::Matrix3Xf sensor = (pose.inverse().cast<float>() * world).eval();
    LabelBox b;
    b.id = "100";
    b.centre = pose.inverse() * (box_at(i) + Eigen::Vector3d(0, 0, 1.3));
    b.size = Eigen::Vector3d(8.0, 2.6, 2.8);  // room for the truck's 1.5 m of travel in 1 s
    boxes.push_back({b});
    points.push_back(points_in_boxes(sensor, world, boxes.back(), 0.1, ground_band));
    poses.push_back(pose);
    times.push_back(t);
  }
  Verdicts v;
  const auto speeds = object_speeds(boxes, points, poses, times, 1.0);
  for (const auto& s : speeds) v.speed.push_back(s.at(0));
  const auto centres = moving_boxes(boxes, poses, times, 0.5, 1.0);
  const auto measured = moving_boxes(boxes, poses, times, 0.5, 1.0, &speeds);
  for (int i = 0; i < scans; ++i) {
    v.by_centres.push_back(centres[static_cast<std::size_t>(i)].at(0));
    v.by_points.push_back(measured[static_cast<std::size_t>(i)].at(0));
  }
  return v;
}

int count(const std::vector<bool>& v) {
  int n = 0;
  for (bool b : v) n += b;
  return n;
}

TEST(ObjectSpeeds, AParkedTruckWhoseInterpolatedBoxesCreepStandsOnItsPoints) {
  // Key frames every 10 scans; in between the tool's boxes creep 6 cm a scan and jump back,
  // as truck 101's do on the Pandar64 street.
  const Eigen::Vector3d parked(12, -4.8, 0);
  const auto v = drive_past(
      30, [&](double) -> Eigen::Vector3d { return parked; },
      [&](int i) -> Eigen::Vector3d { return parked + Eigen::Vector3d(2.5 + 0.06 * (i % 10), 1.2, 0); });
  EXPECT_GT(count(v.by_centres), 5);  // the centres' line reads the creep: 0.6 m/s
  EXPECT_EQ(count(v.by_points), 0);
  for (double s : v.speed) EXPECT_LT(s, 0.05);  // measured in every scan, all but standing
}

TEST(ObjectSpeeds, ATruckDrivingUnderCopiedBoxesMovesOnItsPoints) {
  const Eigen::Vector3d start(10, -4.8, 0);
  const auto v = drive_past(
      11, [&](double t) -> Eigen::Vector3d { return start + Eigen::Vector3d(1.5 * t, 0, 0); },
      [&](int) -> Eigen::Vector3d { return start + Eigen::Vector3d(3.25, 1.2, 0); });
  EXPECT_EQ(count(v.by_centres), 0);
  EXPECT_EQ(count(v.by_points), 11);
  for (double s : v.speed) EXPECT_NEAR(s, 1.5, 0.03);
}

TEST(ObjectSpeeds, TheRoadInsideTheBoxDoesNotHoldTheMotionAtZero) {
  const Eigen::Vector3d start(10, -4.8, 0);
  auto truck_at = [&](double t) -> Eigen::Vector3d { return start + Eigen::Vector3d(1.5 * t, 0, 0); };
  auto box_at = [&](int) -> Eigen::Vector3d { return start + Eigen::Vector3d(3.25, 1.2, 0); };
  const auto v = drive_past(11, truck_at, box_at, true);
  for (double s : v.speed) EXPECT_NEAR(s, 1.5, 0.03);
  // The road's own points, more than the truck's, fix only the height, even left in.
  const auto with_road = drive_past(11, truck_at, box_at, true, 0.0);
  for (double s : with_road.speed) EXPECT_NEAR(s, 1.5, 0.03);
}

TEST(ObjectSpeeds, WhatCannotBeMeasuredIsLeftToTheCentres) {
  std::vector<std::vector<LabelBox>> boxes(2);
  LabelBox b;
  b.id = "7";
  boxes[0] = {b};
  boxes[1] = {b};
  const std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  const std::vector<double> times{0.0, 0.1};
  const Eigen::Matrix3Xf few = truck(Eigen::Vector3d::Zero()).leftCols(29);
  const Eigen::Matrix3Xf many = truck(Eigen::Vector3d::Zero());
  // Too few points on one side.
  auto s = object_speeds(boxes, {{few}, {many}}, poses, times, 1.0);
  EXPECT_TRUE(std::isnan(s[0][0]) && std::isnan(s[1][0]));
  // A fit no better than 0.1 m: the second sighting is another shape (a sparse cloud, points
  // about 0.4 m apart, in the truck's 5 m cube; std::rand is unseeded, so fixed).
  const Eigen::Matrix3Xf scatter = (Eigen::Matrix3Xf::Random(3, 2000).array() + 1.0f) * 2.5f;
  s = object_speeds(boxes, {{many}, {scatter}}, poses, times, 1.0);
  EXPECT_TRUE(std::isnan(s[0][0]));
  // One sighting in the window.
  s = object_speeds(boxes, {{many}, {many}}, poses, times, 0.05);
  EXPECT_TRUE(std::isnan(s[0][0]));
  // Both measurable: standing.
  s = object_speeds(boxes, {{many}, {many}}, poses, times, 1.0);
  EXPECT_NEAR(s[0][0], 0.0, 1e-9);
}

}  // namespace
}  // namespace cleanmap
