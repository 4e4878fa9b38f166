// The tracker on hand-made object lists: association, confirmation and the window.
#include "dynamics/object_tracker.hpp"

#include <gtest/gtest.h>

#include <array>

namespace cleanmap {
namespace {

ScanObject box(float x, float y, float size, bool moving) {
  ScanObject o;
  o.centroid = {x, y, 0.8f};
  o.lo = o.centroid - Eigen::Vector3f::Constant(size / 2);
  o.hi = o.centroid + Eigen::Vector3f::Constant(size / 2);
  o.points = 50;
  o.seen_moving = moving;
  return o;
}

// A scan at 10 Hz holding the given objects, one full-resolution point each, dynamic where
// the object is seen moving.
ScoredScan scan_of(std::size_t index, const std::vector<ScanObject>& objects) {
  ScoredScan s;
  s.index = index;
  s.scan.stamp = 0.1 * static_cast<double>(index);
  s.objects.objects = objects;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    s.objects.of_point.push_back(static_cast<std::int32_t>(k));
    s.dynamic.push_back(objects[k].seen_moving ? 1 : 0);
  }
  return s;
}

std::vector<ScoredScan> run(ObjectTracker& tracker, std::vector<ScoredScan> scans) {
  std::vector<ScoredScan> out;
  for (auto& s : scans) {
    for (auto& r : tracker.push(std::move(s))) out.push_back(std::move(r));
  }
  for (auto& r : tracker.finish()) out.push_back(std::move(r));
  return out;
}

TEST(ObjectTracker, MatchesAreOneToOneNearestFirstAndSizeCompatible) {
  // A car moved 0.8 m beside a parked one 3 m away; a small object merged into a wall.
  const std::vector<ScanObject> a{box(0, 0, 2, true), box(3, 0, 2, false), box(10, 0, 0.5f, true)};
  const std::vector<ScanObject> b{box(3, 0, 2, false), box(0.8f, 0, 2, false), box(10, 0, 8, false)};
  const auto m = match_objects(a, b, 1.0);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(std::size_t{1}, std::size_t{0}));  // the parked car: 0 m
  EXPECT_EQ(m[1], std::make_pair(std::size_t{0}, std::size_t{1}));  // the car: 0.8 m
}

TEST(ObjectTracker, AConfirmedMoverStaysMovingWhereTheNormalsMissIt) {
  // Seen moving in scans 0 and 1 (1 m apart: confirmed), then stopped at x = 1.5 for scans
  // 2-8; a bush beside the road seen moving once, in scan 0, never moves.
  std::vector<ScoredScan> scans;
  for (std::size_t i = 0; i < 9; ++i) {
    const float x = i == 0 ? 0.0f : i == 1 ? 1.0f : 1.5f;
    scans.push_back(scan_of(i, {box(x, 0, 2, i < 2), box(0, 6, 1, i == 0)}));
  }
  ObjectTracker tracker(TrackRule{}, 5, 0.6);
  const auto out = run(tracker, std::move(scans));
  ASSERT_EQ(out.size(), 9u);
  for (const auto& s : out) {
    ASSERT_EQ(s.index, static_cast<std::size_t>(&s - out.data()));
    // Within 5 scans of a confirmed sighting (scans 0, 1): moving; later ones are not.
    EXPECT_EQ(s.dynamic[0], s.index <= 6 ? 1 : 0) << "scan " << s.index;
    EXPECT_EQ(s.dynamic[1], s.index == 0 ? 1 : 0) << "scan " << s.index;
    EXPECT_EQ(s.tracked_points, s.index >= 2 && s.index <= 6 ? 1u : 0u);
  }
}

TEST(ObjectTracker, AnObjectSeenMovingInPlaceIsNotConfirmed) {
  // Seen "moving" in every other scan but its centroid only jitters (0.2 m < the 0.6 m radius).
  std::vector<ScoredScan> scans;
  for (std::size_t i = 0; i < 8; ++i) scans.push_back(scan_of(i, {box(i % 2 ? 0.2f : 0.0f, 0, 1, i % 2 == 0)}));
  ObjectTracker tracker(TrackRule{}, 3, 0.6);
  for (const auto& s : run(tracker, std::move(scans))) EXPECT_EQ(s.tracked_points, 0u) << "scan " << s.index;
}

TEST(ObjectTracker, AtTheLogsEndsItMarksTracksSeenMovingWhereTheWindowHadBothSides) {
  // Six scans; the first and the last were scored with one side of the window. A car drives
  // 1 m a scan, seen moving in every scan. A wall comes into view at the end: seen "moving" in
  // scans 4 and 5 as more of it appears (its centroid shifts 0.8 m), which only the last scan,
  // scored with the past alone, can confirm with. A far static blob is seen moving in scans
  // 1-4, its centroid jittering 0.75 m: a track as confirmed as the car's (the whole log's
  // visibility tells them apart: WholeLogVote.AtALogEnd*).
  const std::array<float, 6> blob_x{0.0f, 0.0f, 0.75f, 0.0f, 0.1f, 0.1f};
  std::vector<ScoredScan> scans;
  for (std::size_t i = 0; i < 6; ++i) {
    scans.push_back(scan_of(
        i, {box(static_cast<float>(i), 0, 2, true), box(i == 5 ? 10.8f : 10.0f, 8, 3, i >= 4),
            box(blob_x[i], -8, 3, i >= 1 && i <= 4)}));
    scans.back().scans_before = i > 0 ? 1 : 0;
    scans.back().scans_after = i < 5 ? 1 : 0;
  }
  ObjectTracker tracker(TrackRule{}, 4, 0.6);
  const auto out = run(tracker, std::move(scans));
  ASSERT_EQ(out.size(), 6u);
  EXPECT_EQ(out[0].on_moving_track, (std::vector<std::uint8_t>{1, 0, 1}));  // from scans 1-4
  EXPECT_EQ(out[5].on_moving_track, (std::vector<std::uint8_t>{1, 0, 1}));
  for (std::size_t i = 1; i < 5; ++i) EXPECT_TRUE(out[i].on_moving_track.empty()) << "scan " << i;
  // The tracker's own labels are unchanged by it: the wall counts as confirmed there (scans 4
  // and 5, 0.8 m apart).
  EXPECT_EQ(out[5].dynamic, (std::vector<std::uint8_t>{1, 1, 1}));
}

TEST(GridComponents, TouchingCellsJoinAndAGapOfACellSplits) {
  // Cells of 0.3 m: x = 0.05, 0.35 (touching cells), 0.65 (touching again), then 1.25 (a gap of
  // one empty cell), and an excluded point at 0.95 that would have bridged it.
  Eigen::Matrix3Xf p(3, 5);
  p << 0.05f, 0.35f, 0.65f, 1.25f, 0.95f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0;
  const auto id = grid_components(p, {1, 1, 1, 1, 0}, 0.3);
  EXPECT_EQ(id, (std::vector<std::int32_t>{0, 0, 0, 1, -1}));
  // Diagonal neighbours touch too.
  Eigen::Matrix3Xf q(3, 2);
  q << 0.1f, 0.4f, 0.1f, 0.4f, 0.1f, 0.4f;
  EXPECT_EQ(grid_components(q, {1, 1}, 0.3), (std::vector<std::int32_t>{0, 0}));
}

TEST(DescribeObjects, SpecksAndBuildingsAreNoObjects) {
  // Cluster 0: three points, two dynamic (seen moving); cluster 1: two points (a speck, under
  // min_points 3); cluster 2: 20 m wide (a building front); -1: ground.
  Eigen::Matrix3Xf p(3, 8);
  p << 0, 0.2f, 0.4f, 5, 5.1f, 10, 30, 3,  //
      0, 0, 0, 0, 0, 0, 0, 0,               //
      1, 1, 1, 1, 1, 1, 1, 0;
  const std::vector<std::int32_t> id{0, 0, 0, 1, 1, 2, 2, -1};
  const std::vector<std::uint8_t> dynamic{1, 1, 0, 1, 1, 0, 0, 0};
  const std::vector<std::int32_t> owner{0, 1, 2, 3, 4, 5, 6, 7, 0};  // a full point per downsampled one, and one more
  const auto out = describe_objects(p, id, dynamic, 12.0, 3, owner);
  ASSERT_EQ(out.objects.size(), 1u);
  EXPECT_EQ(out.objects[0].points, 3u);
  EXPECT_TRUE(out.objects[0].seen_moving);
  EXPECT_FLOAT_EQ(out.objects[0].centroid.x(), 0.2f);
  EXPECT_EQ(out.of_point, (std::vector<std::int32_t>{0, 0, 0, -1, -1, -1, -1, -1, 0}));
  // With min_points 2 the speck is an object too.
  EXPECT_EQ(describe_objects(p, id, dynamic, 12.0, 2, owner).objects.size(), 2u);
}

TEST(ObjectTracker, OffPassesScansThroughAtOnce) {
  ObjectTracker tracker(TrackRule{false, 15.0}, 5, 0.6);
  EXPECT_EQ(tracker.push(scan_of(0, {box(0, 0, 1, true)})).size(), 1u);
  EXPECT_TRUE(tracker.finish().empty());
}

}  // namespace
}  // namespace cleanmap
