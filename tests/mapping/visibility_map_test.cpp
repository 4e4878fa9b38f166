// The whole log's visibility: exact counts on hand-made rays, the OctoMap weighing of them,
// and the rules that keep walls, foliage and the ground out of it.
#include "mapping/visibility_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "mapping/cell_set.hpp"
#include "mapping/whole_log_vote.hpp"

namespace cleanmap {
namespace {

Eigen::Matrix3Xf one(float x, float y, float z) {
  Eigen::Matrix3Xf m(3, 1);
  m << x, y, z;
  return m;
}

const Eigen::Vector3d kOrigin(0.05, 0.05, 0.05);  // a cell centre: rays leave their own cell cleanly

TEST(CellSet, VisitsWhatIsInOneSetAndNotTheOther) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> near(32768 - 60, 32768 + 60);
  CellSet u, in, out;
  std::set<CellSet::Key> tu;
  for (int i = 0; i < 5000; ++i) {
    const CellSet::Key k{static_cast<std::uint16_t>(near(rng)), static_cast<std::uint16_t>(near(rng)),
                         static_cast<std::uint16_t>(near(rng))};
    u.insert(k);
    tu.insert(k);
    if (i % 3 == 0) in.insert(k);
    if (i % 5 == 0) out.insert(k);
  }
  std::set<CellSet::Key> visited;
  u.for_each_also_in(in, out, [&](const CellSet::Key& k) { visited.insert(k); });
  for (const auto& k : tu) EXPECT_EQ(visited.count(k) == 1, in.contains(k) && !out.contains(k));
  EXPECT_EQ(visited.size() <= tu.size(), true);
}

TEST(CellSet, TheTableMortonOfATileIsTheInterleaveOfItsCells) {
  for (std::uint16_t x = 0; x < 32; ++x) {
    for (std::uint16_t y = 0; y < 32; ++y) {
      for (std::uint16_t z = 0; z < 32; ++z) {
        const CellSet::Key k{static_cast<std::uint16_t>(x + 96), static_cast<std::uint16_t>(y + 32 * 7), z};
        const auto m = cell_set_detail::local_morton(k);
        ASSERT_EQ(m, morton_code(x, y, z));
        ASSERT_EQ(cell_set_detail::local_cell(m), (CellSet::Key{x, y, z}));
      }
    }
  }
}

// Scan 0 hits something at x = 5.05; scans 1-3 see a wall at x = 9.05 through that place.
VisibilityMap mover_then_wall(double margin) {
  VisibilityConfig c;
  c.resolution = 0.1;
  c.margin = margin;
  VisibilityMap map(c);
  map.add_hits(one(5.05f, 0.05f, 0.05f));
  for (int s = 1; s <= 3; ++s) map.add_hits(one(9.05f, 0.05f, 0.05f));
  map.add_rays(one(5.05f, 0.05f, 0.05f), kOrigin);
  for (int s = 1; s <= 3; ++s) map.add_rays(one(9.05f, 0.05f, 0.05f), kOrigin);
  return map;
}

TEST(VisibilityMap, CountsHitsAndCrossingsOncePerScan) {
  const VisibilityMap map = mover_then_wall(0.25);
  const auto mover = map.counts({5.05f, 0.05f, 0.05f});
  EXPECT_EQ(mover.hits, 1);
  EXPECT_EQ(mover.crossed, 3);
  const auto wall = map.counts({9.05f, 0.05f, 0.05f});
  EXPECT_EQ(wall.hits, 3);
  EXPECT_EQ(wall.crossed, 0);
  // The margin: a ray ending at 5.05 stops 0.25 m short, so the cells from 4.8 on are not
  // crossed by it (the wall's rays do cross them).
  EXPECT_EQ(map.counts({6.05f, 0.05f, 0.05f}).hits, 0);  // never hit: not counted at all
  EXPECT_EQ(map.cells(), 2u);
}

TEST(WholeLogVote, TheCleanMapKeepsWhatTheLogSawStandingAtLeastAsOftenAsGoneThrough) {
  const VisibilityMap map =
      mover_then_wall(VisibilityConfig{}.margin);  // the wall's rays go through the mover
  EXPECT_EQ(map.counts({5.05f, 0.05f, 0.05f}).through, 3);
  Eigen::Matrix3Xf points(3, 3);
  points << 5.05f, 9.05f, 9.05f, 0.05f, 0.05f, 0.05f, 0.05f, 0.05f, 0.05f;
  EXPECT_EQ(seen_standing(map, points, {0, 1}), (std::vector<std::int32_t>{1}));
  EXPECT_EQ(seen_standing(map, points, {2, 0}),
            (std::vector<std::int32_t>{2}));  // only among `among`
  // Something at 5.05 hit in h scans alone, and the wall behind it in 3 scans alone: gone
  // through 3 times. Standing when h >= 3.
  for (int h : {2, 3}) {
    VisibilityConfig c;
    c.resolution = 0.1;
    VisibilityMap log(c);
    for (int s = 0; s < h; ++s) log.add_hits(one(5.05f, 0.05f, 0.05f));
    for (int s = 0; s < 3; ++s) log.add_hits(one(9.05f, 0.05f, 0.05f));
    for (int s = 0; s < h; ++s) log.add_rays(one(5.05f, 0.05f, 0.05f), kOrigin);
    for (int s = 0; s < 3; ++s) log.add_rays(one(9.05f, 0.05f, 0.05f), kOrigin);
    ASSERT_EQ(log.counts({5.05f, 0.05f, 0.05f}).through, 3) << h;
    EXPECT_EQ(seen_standing(log, one(5.05f, 0.05f, 0.05f), {0}).size(), h == 3 ? 1u : 0u) << h;
  }
}

TEST(VisibilityMap, MovedWhenTheLogWentThroughItInMoreScansThanHitIt) {
  // Something at 5.05 hit in h scans, the wall behind it in k others that see through it. The
  // OctoMap's weights (+0.847 a hit at p_hit 0.7, -0.405 a crossing at p_miss 0.4, free at
  // -1.386) call none of these free: 1 hit against 2 crossings is +0.037. Gone through in more
  // scans than hit, the cell moved.
  for (const auto& [h, k] : std::vector<std::pair<int, int>>{{1, 1}, {1, 2}, {2, 2}, {2, 3}}) {
    VisibilityConfig c;
    c.resolution = 0.1;
    VisibilityMap map(c);
    for (int s = 0; s < h; ++s) map.add_hits(one(5.05f, 0.05f, 0.05f));
    for (int s = 0; s < k; ++s) map.add_hits(one(9.05f, 0.05f, 0.05f));
    for (int s = 0; s < h; ++s) map.add_rays(one(5.05f, 0.05f, 0.05f), kOrigin);
    for (int s = 0; s < k; ++s) map.add_rays(one(9.05f, 0.05f, 0.05f), kOrigin);
    ASSERT_EQ(map.counts({5.05f, 0.05f, 0.05f}).through, k);
    EXPECT_EQ(map.moved_through(one(5.05f, 0.05f, 0.05f))[0], k > h ? 1 : 0) << h << " " << k;
    // The wall itself: hit k times, never crossed.
    EXPECT_EQ(map.moved_through(one(9.05f, 0.05f, 0.05f))[0], 0);
  }
}

TEST(VisibilityMap, MovedOnlyWhenGoneThroughOutsideTheScansThatHitIt) {
  // Nine scans; each hits the cell at 5.05 or, seeing through it, the wall behind. A mover hit
  // in scans 0-2 and gone through in 3-8 left. A thin pole hit in scans 1, 4 and 7 and grazed
  // past in the other six stands: only scans 0 and 8 went through it before its first hit or
  // after its last. Both are hit in 3 scans and gone through in 6; the OctoMap's weights call
  // neither free (3 x 0.847 - 6 x 0.405 = +0.11).
  for (const auto& [hit_in, moved] :
       std::vector<std::pair<std::vector<int>, int>>{{{0, 1, 2}, 1}, {{1, 4, 7}, 0}}) {
    VisibilityConfig c;
    c.resolution = 0.1;
    VisibilityMap map(c);
    auto scan = [&](int s) {
      const bool hit = std::find(hit_in.begin(), hit_in.end(), s) != hit_in.end();
      return one(hit ? 5.05f : 9.05f, 0.05f, 0.05f);
    };
    for (int s = 0; s < 9; ++s) map.add_hits(scan(s));
    for (int s = 0; s < 9; ++s) map.add_rays(scan(s), kOrigin);
    const auto counts = map.counts({5.05f, 0.05f, 0.05f});
    ASSERT_EQ(counts.hits, 3);
    ASSERT_EQ(counts.through, 6);
    EXPECT_EQ(counts.first_hit, hit_in.front());
    EXPECT_EQ(counts.last_hit, hit_in.back());
    EXPECT_EQ(counts.through_apart, moved ? 6 : 2);
    EXPECT_EQ(map.moved_through(one(5.05f, 0.05f, 0.05f))[0], moved);
  }
}

TEST(VisibilityMap, ACellBesideAnOccupiedOneDidNotMove) {
  // As above with k = 8 crossings, but a post stands in the next cell, hit in every scan: a
  // ray that grazes a surface crosses the cells it lies in, a mover leaves free space around.
  VisibilityConfig c;
  c.resolution = 0.1;
  VisibilityMap map(c);
  map.add_hits(one(5.05f, 0.05f, 0.05f));
  for (int s = 0; s < 8; ++s) {
    map.add_hits(one(9.05f, 0.05f, 0.05f));
    map.add_hits(one(5.05f, 0.15f, 0.05f));
  }
  map.add_rays(one(5.05f, 0.05f, 0.05f), kOrigin);
  for (int s = 0; s < 8; ++s) map.add_rays(one(9.05f, 0.05f, 0.05f), kOrigin);
  EXPECT_EQ(map.counts({5.05f, 0.05f, 0.05f}).crossed, 8);
  EXPECT_EQ(map.moved_through(one(5.05f, 0.05f, 0.05f))[0], 0);
}

TEST(VisibilityMap, AScanThatHitsACellDoesNotAlsoCrossIt) {
  // Foliage: every scan hits the bush's cell and sees through it to the wall behind. Nothing
  // moved there, and no crossing is counted.
  VisibilityConfig c;
  c.resolution = 0.1;
  VisibilityMap map(c);
  Eigen::Matrix3Xf scan(3, 2);
  scan << 5.05f, 9.05f, 0.05f, 0.05f, 0.05f, 0.05f;
  for (int s = 0; s < 10; ++s) map.add_hits(scan);
  for (int s = 0; s < 10; ++s) map.add_rays(scan, kOrigin);
  EXPECT_EQ(map.counts({5.05f, 0.05f, 0.05f}).hits, 10);
  EXPECT_EQ(map.counts({5.05f, 0.05f, 0.05f}).crossed, 0);
}

// A flat roof in the bottom of its cell: hits at z = 1.41 over the whole of x in [5.0, 5.2),
// y in [0, 0.2), the cell's z range [1.4, 1.6).
Eigen::Matrix3Xf roof() {
  Eigen::Matrix3Xf m(3, 100);
  for (int i = 0; i < 100; ++i) m.col(i) = Eigen::Vector3f(5.01f + 0.02f * (i % 10), 0.01f + 0.02f * (i / 10), 1.41f);
  return m;
}

TEST(VisibilityMap, ARayOverARoofDoesNotCrossItsCell) {
  // The sensor at 1.5 m looks over the roof (hit once, by scan 0) at a wall 9 m away: its ray
  // passes the roof's cell at z = 1.5, 9 cm above the hits. With whole cells that counted as
  // seeing through the roof; with the hits' level it does not, and a ray that comes down to the
  // roof's level (1.417 m there) does.
  const Eigen::Vector3d origin(0.1, 0.1, 1.5);
  for (const double extent : {0.05, 0.1}) {
    VisibilityConfig c;
    c.extent_margin = extent;
    VisibilityMap map(c);
    map.add_hits(roof());
    const auto over = one(9.1f, 0.1f, 1.5f), down = one(9.1f, 0.1f, 1.35f);
    for (int s = 0; s < 3; ++s) map.add_hits(over);
    map.add_hits(down);
    for (int s = 0; s < 3; ++s) map.add_rays(over, origin);
    // Within 0.1 m of the roof's level, the ray 9 cm over it reaches it.
    EXPECT_EQ(map.counts({5.1f, 0.1f, 1.41f}).crossed, extent >= 0.1 ? 3 : 0) << extent;
    map.add_rays(down, origin);
    EXPECT_EQ(map.counts({5.1f, 0.1f, 1.41f}).crossed, extent >= 0.1 ? 4 : 1) << extent;
  }
  // One scan with both rays: the ray that reaches the roof's level counts the cell once when
  // it walks there; walked after the ray over the roof, it stops at the cells they share
  // (walk_ray's early stop) before it reaches the roof, and the cell is left uncounted. That
  // errs towards static, the side a clean map can afford.
  for (const bool down_first : {true, false}) {
    VisibilityMap map{VisibilityConfig{}};
    map.add_hits(roof());
    Eigen::Matrix3Xf both(3, 2);
    both.col(down_first ? 0 : 1) = Eigen::Vector3f(9.1f, 0.1f, 1.35f);
    both.col(down_first ? 1 : 0) = Eigen::Vector3f(9.1f, 0.1f, 1.5f);
    map.add_hits(both);
    map.add_rays(both, origin);
    EXPECT_EQ(map.counts({5.1f, 0.1f, 1.41f}).crossed, down_first ? 1 : 0) << down_first;
  }
}

TEST(VisibilityMap, ARayBetweenTheRowsOfAFarCarStillCrossesItsSide) {
  // One row of a car's side (y = 0.1, z = 1.5, along x), thin along y and z: a ray through the
  // side 8 cm above the row, between two rows, passes the side's level along y and counts.
  VisibilityMap map{VisibilityConfig{}};
  Eigen::Matrix3Xf row(3, 10);
  for (int i = 0; i < 10; ++i) row.col(i) = Eigen::Vector3f(5.01f + 0.02f * i, 0.1f, 1.5f);
  map.add_hits(row);
  const Eigen::Vector3d origin(5.1, -8.0, 1.58);
  const auto wall = one(5.1f, 9.0f, 1.58f);
  map.add_hits(wall);
  map.add_rays(wall, origin);
  EXPECT_EQ(map.counts({5.1f, 0.1f, 1.5f}).crossed, 1);
}

TEST(VisibilityMap, BadSettingsAreNamed) {
  VisibilityConfig c;
  c.margin = -1;
  EXPECT_THROW(VisibilityMap{c}, std::runtime_error);
  c = {};
  c.resolution = std::nan("");
  EXPECT_THROW(VisibilityMap{c}, std::runtime_error);
  c = {};
  c.extent_margin = -0.01;
  EXPECT_THROW(VisibilityMap{c}, std::runtime_error);
  c = {};
  c.angular_margin = std::nan("");
  EXPECT_THROW(VisibilityMap{c}, std::runtime_error);
  c.angular_margin = -0.001;
  EXPECT_THROW(VisibilityMap{c}, std::runtime_error);
}

// A 1 m cube of points at `x` (on a 0.2 m lattice), as one scan sees it.
Eigen::Matrix3Xf cube(float x) {
  std::vector<Eigen::Vector3f> p;
  for (float a = 0; a < 1.0f; a += 0.2f) {
    for (float b = 0; b < 1.0f; b += 0.2f) {
      for (float c = 0; c < 1.0f; c += 0.2f) p.emplace_back(x + a, b + 0.1f, c + 0.5f);
    }
  }
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

// A 4 m x 4 m wall across x = `x` (0.2 m apart), as one scan sees it.
Eigen::Matrix3Xf wall_at(float x) {
  Eigen::Matrix3Xf m(3, 400);
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) m.col(i * 20 + j) << x, -1.5f + 0.2f * static_cast<float>(i), -1.0f + 0.2f * static_cast<float>(j);
  }
  return m;
}

// The wall at x = 12 hit in `wall_scans` scans from (0, 0.5, 1), and `behind_scans` more that
// see through it to a wall at x = 15 (the wall gone for them).
VisibilityMap wall_seen(int wall_scans, int behind_scans) {
  VisibilityMap map({});
  const auto wall = wall_at(12.0f), behind = wall_at(15.0f);
  const Eigen::Vector3d origin(0, 0.5, 1.0);
  for (int s = 0; s < wall_scans; ++s) map.add_hits(wall);
  for (int s = 0; s < behind_scans; ++s) map.add_hits(behind);
  for (int s = 0; s < wall_scans; ++s) map.add_rays(wall, origin);
  for (int s = 0; s < behind_scans; ++s) map.add_rays(behind, origin);
  return map;
}

TEST(WholeLogVote, AnObjectInSpaceTheLogSawThroughIsDynamic) {
  // A box stands at x = 6 in scan 0; ten later scans see a wall at x = 12 through where it was.
  VisibilityMap map({});
  const auto box = cube(6.0f), wall = wall_at(12.0f);
  map.add_hits(box);
  for (int s = 0; s < 10; ++s) map.add_hits(wall);
  map.add_rays(box, Eigen::Vector3d(0, 0.5, 1.0));
  for (int s = 0; s < 10; ++s) map.add_rays(wall, Eigen::Vector3d(0, 0.5, 1.0));
  auto no_ground = [](const Eigen::Matrix3Xf& sub) { return std::vector<std::uint8_t>(static_cast<std::size_t>(sub.cols()), 0); };
  std::vector<std::uint8_t> dynamic(static_cast<std::size_t>(box.cols()), 0);
  const auto v = judge_with_log(box, dynamic, map, no_ground, kFreeSpaceRule, false);
  EXPECT_GT(v.added, box.cols() / 3);
  // The wall, hit in every scan, stays; and at a log end an object the normals called dynamic
  // that the log saw standing (the wall: hit 10 times, never crossed) is static again.
  std::vector<std::uint8_t> wall_dynamic(static_cast<std::size_t>(wall.cols()), 1);
  const auto w = judge_with_log(wall, wall_dynamic, map, no_ground, kFreeSpaceRule, true);
  EXPECT_EQ(w.added, 0u);
  EXPECT_EQ(w.vetoed, static_cast<std::size_t>(wall.cols()));
  // Inside the log too: no ray of any scan ever crossed the wall's cells, so it never left.
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(wall.cols()), 1);
  EXPECT_EQ(judge_with_log(wall, inside, map, no_ground, kFreeSpaceRule, false).vetoed,
            static_cast<std::size_t>(wall.cols()));
}

TEST(WholeLogVote, AtALogEndAnObjectOnATrackSeenMovingInsideTheLogIsJudgedAsInsideIt) {
  // A wall at x = 12 hit in ten scans, three of which see through it to x = 15: crossed less
  // often than hit (a car driving alongside, its body hitting the cells it leaves), gone
  // through in more than one scan per 25 that hit it. At a log end the normals call it
  // dynamic. One of its points lies on a track the tracker saw moving inside the log: the
  // whole object (one cluster) is judged by the rule inside the log, and stays dynamic.
  // Without that point it is static again (the log-end rule).
  const VisibilityMap map = wall_seen(10, 3);
  const auto wall = wall_at(12.0f);
  auto no_ground = [](const Eigen::Matrix3Xf& sub) {
    return std::vector<std::uint8_t>(static_cast<std::size_t>(sub.cols()), 0);
  };
  const auto n = static_cast<std::size_t>(wall.cols());
  std::vector<std::uint8_t> track(n, 0);
  track[n / 2] = 1;
  std::vector<std::uint8_t> end(n, 1);
  EXPECT_EQ(judge_with_log(wall, end, map, no_ground, kFreeSpaceRule, true, 0.2, track).vetoed, 0u);
  EXPECT_EQ(static_cast<std::size_t>(std::count(end.begin(), end.end(), 1)), n);
  std::vector<std::uint8_t> untracked(n, 1);
  EXPECT_EQ(judge_with_log(wall, untracked, map, no_ground, kFreeSpaceRule, true, 0.2, {}).vetoed,
            n);
  // A wall no ray ever went through (a far static blob whose centroid jitters, confirmed as a
  // track): static at a log end, tracked or not, as it is inside the log.
  const VisibilityMap solid = wall_seen(10, 0);
  std::vector<std::uint8_t> blob(n, 1);
  EXPECT_EQ(judge_with_log(wall, blob, solid, no_ground, kFreeSpaceRule, true, 0.2, track).vetoed,
            n);
}

TEST(WholeLogVote, InsideTheLogTheNormalsKeepWhatTheLogSawThroughOncePer25Hits) {
  // A wall at x = 12 hit in ten scans, and three scans that see through it to x = 15 (the wall
  // gone for them: something that crawls, occupied most of the time).
  const VisibilityMap map = wall_seen(10, 3);
  const auto wall = wall_at(12.0f);
  auto no_ground = [](const Eigen::Matrix3Xf& sub) { return std::vector<std::uint8_t>(static_cast<std::size_t>(sub.cols()), 0); };
  int through = 0, hits = 0;
  for (Eigen::Index i = 0; i < wall.cols(); ++i) {
    through += map.counts(wall.col(i)).through;
    hits += map.counts(wall.col(i)).hits;
  }
  // Some of its cells, where the rays cross the hits' level (64 a scan): at least one crossing
  // per 25 hits over the whole wall.
  ASSERT_GE(through * 25, hits);
  // Inside the log the normals keep their call: it left its place.
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(wall.cols()), 1);
  EXPECT_EQ(judge_with_log(wall, inside, map, no_ground, kFreeSpaceRule, false).vetoed, 0u);
  EXPECT_EQ(std::count(inside.begin(), inside.end(), 1), wall.cols());
  // At a log end, hit more often than crossed, it stood: static.
  std::vector<std::uint8_t> end(static_cast<std::size_t>(wall.cols()), 1);
  EXPECT_EQ(judge_with_log(wall, end, map, no_ground, kFreeSpaceRule, true).vetoed, static_cast<std::size_t>(wall.cols()));
}

TEST(WholeLogVote, InsideTheLogAnObjectSeenThroughInUnderOneScanPer25ThatHitItIsStatic) {
  // A fence at x = 12 hit in 30 scans; one scan sees through it to x = 15 (a gap in the slats).
  // Even if that scan went through every cell, 400 crossings against 30 x 400 hits is under
  // one per 25: a static porous surface, not something that left.
  VisibilityMap map({});
  const auto fence = wall_at(12.0f), behind = wall_at(15.0f);
  const Eigen::Vector3d origin(0, 0.5, 1.0);
  for (int s = 0; s < 30; ++s) map.add_hits(fence);
  map.add_hits(behind);
  for (int s = 0; s < 30; ++s) map.add_rays(fence, origin);
  map.add_rays(behind, origin);
  auto no_ground = [](const Eigen::Matrix3Xf& sub) { return std::vector<std::uint8_t>(static_cast<std::size_t>(sub.cols()), 0); };
  int through = 0, hits = 0;
  for (Eigen::Index i = 0; i < fence.cols(); ++i) {
    through += map.counts(fence.col(i)).through;
    hits += map.counts(fence.col(i)).hits;
  }
  ASSERT_GT(through, 0);  // seen through: "never gone through" alone would keep the normals' call
  ASSERT_EQ(hits, 30 * fence.cols());
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(fence.cols()), 1);
  EXPECT_EQ(judge_with_log(fence, inside, map, no_ground, kFreeSpaceRule, false).vetoed,
            static_cast<std::size_t>(fence.cols()));
  EXPECT_EQ(std::count(inside.begin(), inside.end(), 1), 0);
}

}  // namespace
}  // namespace cleanmap
