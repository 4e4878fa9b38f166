#include <cmath>

#include "evaluation/dynamic_metrics.hpp"
#include "evaluation/map_metrics.hpp"
#include "evaluation/trajectory_metrics.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// A straight drive along x at 1 m per frame.
std::vector<Eigen::Isometry3d> straight(int n, double step = 1.0) {
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(step * i, 0, 0);
    poses.push_back(p);
  }
  return poses;
}

TEST(KittiErrors, ConstantScaleDriftGivesThatPercentage) {
  const auto ref = straight(1000);
  const auto est = straight(1000, 1.02);  // 2% too long everywhere
  const auto e = kitti_errors(ref, est);
  EXPECT_NEAR(e.t_err_percent, 2.0, 0.02);
  EXPECT_NEAR(e.r_err_deg_per_100m, 0.0, 1e-9);
  for (double t : e.t_err_by_length) EXPECT_NEAR(t, 2.0, 0.02);
  // Segments start every 10 frames; a 100 m segment needs frames past 100 m of path.
  EXPECT_EQ(e.segments.front().first_frame, 0);
  EXPECT_EQ(e.segments[1].first_frame, 0);
}

TEST(KittiErrors, ConstantYawRateDriftGivesDegreesPer100m) {
  const auto ref = straight(900);
  std::vector<Eigen::Isometry3d> est;
  const double yaw_per_m = 0.01 * M_PI / 180.0;  // 1 deg per 100 m
  for (int i = 0; i < 900; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(yaw_per_m * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(i, 0, 0);
    est.push_back(p);
  }
  const auto e = kitti_errors(ref, est);
  // The devkit ends a segment at the first frame *beyond* its length: a 100 m segment spans
  // 101 frames here, so its error is 1.01 deg per 100 m of nominal length.
  double expected = 0.0;
  for (const auto& s : e.segments) expected += (s.length + 1.0) / s.length;
  expected /= static_cast<double>(e.segments.size());
  EXPECT_NEAR(e.r_err_deg_per_100m, expected, 1e-6);
  EXPECT_NEAR(e.r_err_by_length[0], 1.01, 1e-6);
}

TEST(TrajectoryErrors, RotatedAndShiftedCopyAlignsBackToZero) {
  std::vector<Eigen::Isometry3d> ref, est;
  Eigen::Isometry3d g = Eigen::Isometry3d::Identity();
  g.translate(Eigen::Vector3d(5, -3, 1)).rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.1, 0.2, 1).normalized()));
  for (int i = 0; i < 50; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(i, std::sin(0.2 * i), 0.1 * i);
    p.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    ref.push_back(p);
    est.push_back(g * p);
  }
  EXPECT_GT(absolute_pose_error(ref, est, Alignment::kNone).translation.rmse, 1.0);
  EXPECT_NEAR(absolute_pose_error(ref, est, Alignment::kSE3).translation.rmse, 0.0, 1e-9);
  const auto rpe = relative_pose_error(ref, est, 1);  // relative motion is frame-independent
  EXPECT_NEAR(rpe.translation.max, 0.0, 1e-9);
  EXPECT_NEAR(rpe.rotation.max, 0.0, 1e-5);  // degrees; acos near 1 resolves ~1e-6
  // A scaled copy needs Sim(3).
  std::vector<Eigen::Isometry3d> scaled = ref;
  for (auto& p : scaled) p.translation() *= 0.5;
  EXPECT_GT(absolute_pose_error(ref, scaled, Alignment::kSE3).translation.rmse, 1.0);
  const auto sim = absolute_pose_error(ref, scaled, Alignment::kSim3);
  EXPECT_NEAR(sim.translation.rmse, 0.0, 1e-9);
  EXPECT_NEAR(sim.scale, 2.0, 1e-9);
}

TEST(TrajectoryErrors, RpeOfAKnownStepError) {
  const auto ref = straight(11);
  const auto est = straight(11, 1.1);
  const auto rpe = relative_pose_error(ref, est, 2);
  EXPECT_EQ(rpe.translation.count, 9u);
  EXPECT_NEAR(rpe.translation.rmse, 0.2, 1e-12);
}

TEST(TrajectoryErrors, AssociationPairsNearestStampsOnce) {
  std::vector<StampedPose> ref, est;
  for (int i = 0; i < 10; ++i) ref.push_back({0.1 * i, Eigen::Isometry3d::Identity()});
  for (int i = 0; i < 5; ++i) est.push_back({0.2 * i + 0.004, Eigen::Isometry3d::Identity()});
  est.push_back({5.0, Eigen::Isometry3d::Identity()});  // no partner
  std::vector<Eigen::Isometry3d> r, e;
  associate(ref, est, 0.02, r, e);
  EXPECT_EQ(r.size(), 5u);
  EXPECT_EQ(e.size(), 5u);
}

TEST(TrajectoryErrors, ReferenceIsInterpolatedAtMidSweepStamps) {
  // A reference at the scan stamps (0, 0.1, ...) moving 1 m/s along x; estimates stamped at
  // mid-sweep (+0.05 s), where the sensor was 5 cm further: each pairs with the reference there.
  std::vector<StampedPose> ref, est;
  for (int k = 0; k < 5; ++k) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation().x() = 0.1 * k;
    ref.push_back({0.1 * k, p});
    p.translation().x() += 0.05;
    est.push_back({0.1 * k + 0.05, p});
  }
  est.push_back({0.47, est.back().pose});  // beyond the reference by 0.07 s: left out
  std::vector<Eigen::Isometry3d> r, e;
  interpolate_reference(ref, est, 0.25, 0.02, r, e);
  ASSERT_EQ(r.size(), 4u);  // 0.45 lies beyond the last reference too (0.4), by 0.05 > 0.02
  for (std::size_t k = 0; k < r.size(); ++k) EXPECT_NEAR((r[k].translation() - e[k].translation()).norm(), 0.0, 1e-12);
  associate(ref, est, 0.02, r, e);
  EXPECT_EQ(r.size(), 0u);  // nearest-stamp association finds none within 0.02 s
}

TEST(TrajectoryErrors, HeadingDifferenceTellsCameraFromLidarFrames) {
  // The same drive as KITTI's camera frame (forward = +z) and a lidar frame (forward = +x).
  std::vector<Eigen::Isometry3d> camera, lidar;
  for (int k = 0; k < 10; ++k) {
    Eigen::Isometry3d c = Eigen::Isometry3d::Identity(), l = Eigen::Isometry3d::Identity();
    c.translation().z() = 0.7 * k;
    l.translation().x() = 0.7 * k;
    camera.push_back(c);
    lidar.push_back(l);
  }
  EXPECT_NEAR(heading_difference_deg(camera, lidar), 90.0, 1e-9);
  EXPECT_NEAR(heading_difference_deg(lidar, lidar), 0.0, 1e-6);
  EXPECT_TRUE(std::isnan(heading_difference_deg(std::vector<Eigen::Isometry3d>(3, Eigen::Isometry3d::Identity()), lidar)));
}

TEST(MovingMetrics, IouPrecisionRecall) {
  MovingConfusion c;
  for (int i = 0; i < 6; ++i) count(c, true, true);
  for (int i = 0; i < 2; ++i) count(c, true, false);
  for (int i = 0; i < 4; ++i) count(c, false, true);
  for (int i = 0; i < 100; ++i) count(c, false, false);
  EXPECT_DOUBLE_EQ(c.iou(), 0.5);
  EXPECT_DOUBLE_EQ(c.precision(), 0.75);
  EXPECT_DOUBLE_EQ(c.recall(), 0.6);
  EXPECT_TRUE(std::isnan(MovingConfusion{}.iou()));
}

TEST(MapMetrics, DynamicMapBenchmarkScoresOfHandMadeClouds) {
  // Ground truth: 8 static points and 4 dynamic ones on a 1 m grid.
  Eigen::Matrix3Xf gt(3, 12);
  std::vector<std::uint8_t> dyn(12, 0);
  for (int i = 0; i < 12; ++i) {
    gt.col(i) = Eigen::Vector3f(static_cast<float>(i), 0, 0);
    dyn[static_cast<std::size_t>(i)] = i >= 8;
  }
  // Output keeps 6 static points exactly, one static 3 cm off (kept: within 5 cm), drops one,
  // and keeps one dynamic point 4 cm off (kept) while dropping three.
  Eigen::Matrix3Xf out(3, 8);
  for (int i = 0; i < 6; ++i) out.col(i) = gt.col(i);
  out.col(6) = gt.col(6) + Eigen::Vector3f(0, 0.03f, 0);
  out.col(7) = gt.col(8) + Eigen::Vector3f(0, 0, 0.04f);
  const auto s = score_map(gt, dyn, out);
  EXPECT_EQ(s.static_kept, 7u);
  EXPECT_EQ(s.dynamic_removed, 3u);
  EXPECT_DOUBLE_EQ(s.sa, 87.5);
  EXPECT_DOUBLE_EQ(s.da, 75.0);
  EXPECT_NEAR(s.aa, std::sqrt(87.5 * 75.0), 1e-12);
  EXPECT_NEAR(s.ha, 2 * 87.5 * 75.0 / (87.5 + 75.0), 1e-12);
  EXPECT_DOUBLE_EQ(s.da_ceiling, 100.0);  // no dynamic point lies near a static one
}

TEST(MapMetrics, TheCeilingCountsDynamicPointsNoOutputCanDropWithoutAStaticNeighbour) {
  // Static points at x = 0..3; dynamic ones at 0.04 (within 5 cm of a static point: any output
  // that keeps the static point keeps it), 1.06 (just beyond) and 10 (alone).
  Eigen::Matrix3Xf gt(3, 7);
  gt << 0, 1, 2, 3, 0.04f, 1.06f, 10, Eigen::RowVectorXf::Zero(7), Eigen::RowVectorXf::Zero(7);
  const std::vector<std::uint8_t> dyn{0, 0, 0, 0, 1, 1, 1};
  const auto s = score_map(gt, dyn, gt(Eigen::all, std::vector<int>{0, 1, 2, 3}));
  EXPECT_DOUBLE_EQ(s.sa, 100.0);
  EXPECT_NEAR(s.da, 200.0 / 3, 1e-12);
  EXPECT_NEAR(s.da_ceiling, s.da, 1e-12);  // the static truth as output reaches the ceiling
  EXPECT_NEAR(score_map(gt, dyn, gt, 0.07).da_ceiling, 100.0 / 3, 1e-12);  // 7 cm: 1.06 shadowed too
}

}  // namespace
}  // namespace cleanmap
