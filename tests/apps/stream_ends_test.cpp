// An online run's first and last scan judged with the scans at hand (apps/stream_ends).
#include "apps/stream_ends.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "mapping/free_space_vote.hpp"

namespace cleanmap::app {
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

// The last of four scans hits a wall at x = 12 that the normals call dynamic (one-sided window:
// it looks like something that appeared). `before` is what the three scans before it hit.
std::size_t last_scan_vetoed(float before) {
  StreamEnds ends(9);
  for (int s = 0; s < 3; ++s) ends.add(wall_at(before));
  ends.add(wall_at(12.0f));
  ScoredScan last;
  last.index = 3;
  last.scan = wall_at(12.0f);
  last.dynamic.assign(last.scan.size(), 1);
  last.scans_after = 0;
  const std::size_t vetoed = ends.judge(last, VisibilityConfig{}, kFreeSpaceRule, 0.2);
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

TEST(StreamEnds, AScanNoLongerAtHandIsNotJudged) {
  // Only the last 2 scans are kept: scan 0 is gone, so it keeps the normals' call.
  StreamEnds ends(2);
  for (int s = 0; s < 3; ++s) ends.add(wall_at(12.0f));
  ScoredScan first;
  first.index = 0;
  first.scan = wall_at(12.0f);
  first.dynamic.assign(first.scan.size(), 1);
  EXPECT_EQ(ends.judge(first, VisibilityConfig{}, kFreeSpaceRule, 0.2), 0u);
  EXPECT_TRUE(std::all_of(first.dynamic.begin(), first.dynamic.end(),
                          [](std::uint8_t d) { return d == 1; }));
}

}  // namespace
}  // namespace cleanmap::app
