// Track-level evidence: registered shifts of an object's points, the noise floor they are
// judged against, and the tracker's use of them on slow movers.
#include "dynamics/track_displacement.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "dynamics/object_tracker.hpp"

namespace cleanmap {
namespace {

// A walker's front, seen by a lidar: points on a half cylinder (0.3 m radius, 1.75 m tall)
// facing -x, centred at (x, y).
Eigen::Matrix3Xf walker(float x, float y, int rings = 8, int columns = 5) {
  Eigen::Matrix3Xf p(3, rings * columns);
  for (int r = 0; r < rings; ++r) {
    for (int c = 0; c < columns; ++c) {
      const float a = static_cast<float>(M_PI) * (0.5f + static_cast<float>(c) / static_cast<float>(columns - 1));
      p.col(r * columns + c) = Eigen::Vector3f(x + 0.3f * std::cos(a), y + 0.3f * std::sin(a),
                                               0.1f + 1.65f * static_cast<float>(r) / static_cast<float>(rings - 1));
    }
  }
  return p;
}

TEST(TrackDisplacement, AShiftedObjectRegistersToItsShift) {
  const Eigen::Matrix3Xf a = walker(10, 0);
  const Eigen::Vector3f by(-0.12f, 0.04f, 0.0f);
  const Eigen::Matrix3Xf b = a.colwise() + by;
  const Shift s = register_shift(a, b, 0.3f);
  EXPECT_LT((s.by - by).norm(), 1e-4f) << s.by.transpose();
  EXPECT_FLOAT_EQ(s.overlap, 1.0f);
}

TEST(TrackDisplacement, APartOfAStandingObjectRegistersInPlaceWhereItsCentroidMoves) {
  // The other sighting holds only the walker's upper half (the lower rings occluded): its
  // centroid is 0.47 m higher (over three times the 0.14 m floor), its points are where they were.
  const Eigen::Matrix3Xf a = walker(10, 0);
  const Eigen::Matrix3Xf upper = a.rightCols(a.cols() / 2);
  const Shift s = register_shift(upper, a, 0.3f);
  EXPECT_LT(s.by.norm(), 1e-4f) << s.by.transpose();
  EXPECT_GT((upper.rowwise().mean() - a.rowwise().mean()).norm(), 0.45f);
}

TEST(TrackDisplacement, TheFloorIsThreeSigmaOfPoseRangeAndBeamNoise) {
  // 2 x (0.02^2) + 0.02^2 + (0.003 x 10)^2 = 0.0021
  EXPECT_NEAR(displacement_floor(10, 0.02, 0), 3 * std::sqrt(0.0021), 1e-6);
  // A rotation error adds range x angle per scan: 0.1 degree at 30 m is 5.2 cm.
  const double rot = 30 * 0.1 * M_PI / 180;
  EXPECT_NEAR(displacement_floor(30, 0.0, 0.1), 3 * std::sqrt(2 * rot * rot + 0.0004 + 0.0081), 1e-6);
}

// A scan at 10 Hz holding one object per point set; `seen` marks those the normals saw moving
// (all their points dynamic).
ScoredScan scan_of(std::size_t index, const std::vector<Eigen::Matrix3Xf>& objects, std::vector<bool> seen = {}) {
  seen.resize(objects.size(), false);
  ScoredScan s;
  s.index = index;
  s.scan.stamp = 0.1 * static_cast<double>(index);
  s.scan.pose = Eigen::Isometry3d::Identity();
  Eigen::Index n = 0;
  for (const auto& o : objects) n += o.cols();
  s.scan.points.resize(3, n);
  n = 0;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    ScanObject ob;
    ob.lo = objects[k].rowwise().minCoeff();
    ob.hi = objects[k].rowwise().maxCoeff();
    ob.centroid = objects[k].rowwise().mean();
    ob.points = static_cast<std::uint32_t>(objects[k].cols());
    ob.seen_moving = seen[k];
    s.objects.objects.push_back(ob);
    s.scan.points.middleCols(n, objects[k].cols()) = objects[k];
    for (Eigen::Index i = 0; i < objects[k].cols(); ++i) {
      s.objects.of_point.push_back(static_cast<std::int32_t>(k));
      s.dynamic.push_back(seen[k] ? 1 : 0);
    }
    n += objects[k].cols();
  }
  return s;
}

TEST(TrackDisplacement, AWalkerAtHalfAMetrePerSecondSeenMovingTwiceIsMovingAlongItsTrack) {
  // 0.05 m per scan: 0.2 m over the window of 4, under the centroid rule's 0.6 m, over the
  // 0.14 m floor at 10 m. The normals see it moving in scans 3 and 8 only. Beside it, a
  // standing walker whose lower half comes and goes, which the normals call moving in scan 5.
  ObjectTracker tracker(TrackRule{}, 4, 0.6, 0.02, 0.0);
  std::vector<ScoredScan> out;
  for (std::size_t i = 0; i < 12; ++i) {
    const Eigen::Matrix3Xf standing = walker(10, 5);
    const Eigen::Matrix3Xf half = i % 2 ? Eigen::Matrix3Xf(standing.rightCols(24)) : standing;
    const auto scan = scan_of(i, {walker(10 - 0.05f * static_cast<float>(i), 0), half}, {i == 3 || i == 8, i == 5});
    for (auto& r : tracker.push(scan)) out.push_back(std::move(r));
  }
  for (auto& r : tracker.finish()) out.push_back(std::move(r));
  ASSERT_EQ(out.size(), 12u);
  for (const auto& s : out) {
    // Registered past the floor (0.15 m: three scans) on both sides within the window.
    EXPECT_EQ(s.dynamic.front(), s.index >= 3 && s.index <= 8 ? 1 : 0) << "scan " << s.index;
    EXPECT_EQ(s.dynamic.back(), s.index == 5 ? 1 : 0) << "scan " << s.index;  // the standing one
  }
}

TEST(TrackDisplacement, AWalkerWithinTheNoiseFloorIsNotCalledMoving) {
  // 0.01 m per scan: 4 cm over the window, under the 0.14 m floor; seen moving in scan 5.
  ObjectTracker tracker(TrackRule{}, 4, 0.6, 0.02, 0.0);
  std::size_t moving = 0;
  for (std::size_t i = 0; i < 12; ++i) {
    for (auto& r : tracker.push(scan_of(i, {walker(10 - 0.01f * static_cast<float>(i), 0)}, {i == 5}))) {
      moving += r.index != 5 && r.dynamic.front();
    }
  }
  for (auto& r : tracker.finish()) moving += r.index != 5 && r.dynamic.front();
  EXPECT_EQ(moving, 0u);
}

}  // namespace
}  // namespace cleanmap
