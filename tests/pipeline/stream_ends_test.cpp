// An online run's first and last scan judged with the scans at hand (apps/stream_ends).
#include "pipeline/stream_ends.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "mapping/free_space_vote.hpp"

namespace cleanmap::pipeline {
namespace {

// A 4 m x 4 m wall across x = `x` (0.2 m apart), seen from (0, 0.5, 1) (world frame).
Scan wall_at(float x) {
  Scan s;
  s.points.resize(3, 400);
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      s.points.col(i * 20 + j) << x, -1.5f + 0.2f * static_cast<float>(i),
          -1.0f + 0.2f * static_cast<float>(j);
    }
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0.5, 1.0);
  s.pose = pose;
  return s;
}

// The n-th scan of a sensor standing still, 10 Hz.
// Plans and judges at once, as one stage would.
std::size_t judge_now(StreamEnds& ends, ScoredScan& r) {
  return StreamEnds::judge(r, ends.plan(r), VisibilityConfig{}, kFreeSpaceRule, 0.2);
}

void add(StreamEnds& ends, Scan scan, int n) {
  scan.stamp = 0.1 * n;
  ends.add(scan, StampedPose{scan.stamp, *scan.pose});
}

// The last of four scans hits a wall at x = 12 that the normals call dynamic (one-sided window:
// it looks like something that appeared). `before` is what the three scans before it hit.
std::size_t last_scan_vetoed(float before) {
  StreamEnds ends(9);
  for (int s = 0; s < 3; ++s) add(ends, wall_at(before), s);
  add(ends, wall_at(12.0f), 3);
  ScoredScan last;
  last.index = 3;
  last.scan = wall_at(12.0f);
  last.scan.stamp = 0.3;
  last.dynamic.assign(last.scan.size(), 1);
  last.scans_after = 0;
  const std::size_t vetoed = judge_now(ends, last);
  EXPECT_EQ(static_cast<std::size_t>(std::count(last.dynamic.begin(), last.dynamic.end(), 0)),
            vetoed);
  return vetoed;
}

TEST(StreamEnds, AWallThatCameIntoViewAtTheEndIsStaticAndACarThatArrivedStaysDynamic) {
  // Before, the scans saw a nearer wall at x = 6: no ray reached x = 12 (the wall came into
  // view). Hit once, crossed never: it stood, static.
  EXPECT_EQ(last_scan_vetoed(6.0f), 400u);
  // Before, the scans saw through x = 12 to a wall at x = 15: the place was empty, and what the
  // last scan hits there arrived. Crossed 3 times, hit once: it stays dynamic.
  EXPECT_EQ(last_scan_vetoed(15.0f), 0u);
}

TEST(StreamEnds, TheFirstScanIsJudgedWithTheFirstScansWhichThenGo) {
  // A wall at x = 12 in every scan, never crossed: at either end the normals' call is vetoed.
  // Only the last 2 scans are kept, and the first 2 until the first scan is judged: scan 0
  // left the recent ones when scan 2 came in, and is judged with scans 0 and 1.
  StreamEnds ends(2);
  for (int s = 0; s < 3; ++s) add(ends, wall_at(12.0f), s);
  auto scan = [](std::size_t index, int before, int after) {
    ScoredScan r;
    r.index = index;
    r.scan = wall_at(12.0f);
    r.scan.stamp = 0.1 * static_cast<double>(index);
    r.dynamic.assign(r.scan.size(), 1);
    r.scans_before = before;
    r.scans_after = after;
    return r;
  };
  ScoredScan middle = scan(1, 1, 1);  // two-sided: not an end
  EXPECT_EQ(judge_now(ends, middle), 0u);
  ScoredScan first = scan(0, 0, 2);
  EXPECT_EQ(judge_now(ends, first), 400u);
  // The first scans are gone now: judged again, scan 0 is no longer at hand.
  ScoredScan again = scan(0, 0, 2);
  EXPECT_EQ(judge_now(ends, again), 0u);
  ScoredScan last = scan(2, 2, 0);
  EXPECT_EQ(judge_now(ends, last), 400u);
}

// The judgement is planned in the scoring stage and carried out in the mapping stage, while
// the scoring stage goes on adding scans: it holds the scans as they were when it was planned.
TEST(StreamEnds, AJudgementKeepsTheScansItWasPlannedWith) {
  StreamEnds ends(2);
  for (int s = 0; s < 2; ++s) add(ends, wall_at(12.0f), s);
  ScoredScan first;
  first.index = 0;
  first.scan = wall_at(12.0f);
  first.dynamic.assign(first.scan.size(), 1);
  first.scans_before = 0;
  first.scans_after = 1;
  const auto planned = ends.plan(first);
  ASSERT_EQ(planned.with.size(), 1u);
  // Two more scans push scan 0 out of the recent ones and replace what the ends hold.
  for (int s = 2; s < 4; ++s) add(ends, wall_at(6.0f), s);
  EXPECT_EQ(StreamEnds::judge(first, planned, VisibilityConfig{}, kFreeSpaceRule, 0.2), 400u);
  EXPECT_TRUE(ends.plan(first).with.front().empty());  // planned again: the first scans are gone
}

}  // namespace
}  // namespace cleanmap::pipeline
