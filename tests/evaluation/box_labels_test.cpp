// Which boxes move: the speed of a box's world-frame track, exact on hand-made tracks.
#include "evaluation/box_labels.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "io/error.hpp"

namespace cleanmap {
namespace {

struct Log {
  std::vector<std::vector<LabelBox>> boxes;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<double> times;
};

// One box over 21 scans at 10 Hz, the sensor driving along x at 6 m/s: the box's world
// x is speed * t, plus a hand-drawn box's jitter: +-`jitter` m in the pattern + - - + ....
Log track(double speed, double jitter) {
  const double pattern[4] = {1, -1, -1, 1};
  Log log;
  for (int i = 0; i < 21; ++i) {
    const double t = 0.1 * i;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(6.0 * t, 0, 0);
    LabelBox b;
    b.id = "7";
    b.centre = Eigen::Vector3d(speed * t + jitter * pattern[i % 4] + 10.0 - 6.0 * t, 4.0, 0.0);
    log.boxes.push_back({b});
    log.poses.push_back(pose);
    log.times.push_back(t);
  }
  return log;
}

int moving_scans(const Log& log, double window) {
  const auto m = moving_boxes(log.boxes, log.poses, log.times, 0.5, window);
  int n = 0;
  for (const auto& s : m) n += s.at(0);
  return n;
}

TEST(MovingBoxes, AJitteringParkedBoxStandsOverASecondButMovesBetweenNeighbours) {
  // 0.2 m of jitter: 2 m/s between neighbouring scans, 4 m/s one-sided at the first (the last
  // two agree: 0), at most 0.38 m/s from the line over 1 s (worked out for this pattern).
  const Log parked = track(0.0, 0.2);
  EXPECT_EQ(moving_scans(parked, 0.0), 20);
  EXPECT_EQ(moving_scans(parked, 1.0), 0);
}

TEST(MovingBoxes, ACrawlerAtOneMetrePerSecondMovesInEveryScanThroughTheSameJitter) {
  EXPECT_EQ(moving_scans(track(1.0, 0.2), 1.0), 21);  // the fitted speed stays within 0.71-1.38 m/s
  EXPECT_EQ(moving_scans(track(1.0, 0.0), 1.0), 21);
  EXPECT_EQ(moving_scans(track(0.3, 0.0), 1.0), 0);   // under the threshold, exactly 0.3 m/s
}

TEST(MovingBoxes, ABoxSeenTwiceFallsBackToItsNeighbour) {
  // Too few sightings in the window to fit a line: the speed between the two.
  Log log = track(2.0, 0.0);
  for (std::size_t i = 2; i < log.boxes.size(); ++i) log.boxes[i].clear();
  const auto m = moving_boxes(log.boxes, log.poses, log.times, 0.5, 1.0);
  EXPECT_TRUE(m[0].at(0));
  EXPECT_TRUE(m[1].at(0));
}

TEST(MovingBoxes, AWholeTrackMovesOnceItsObjectMovedInAnyScan) {
  // A truck that drives in and stops (moving only in scan 0), a parked car (never moving).
  LabelBox truck, car;
  truck.id = "100";
  car.id = "7";
  const std::vector<std::vector<LabelBox>> boxes{{truck, car}, {car, truck}, {truck}};
  const std::vector<std::vector<bool>> per_scan{{true, false}, {false, false}, {false}};
  const auto track = moving_tracks(boxes, per_scan);
  const std::vector<std::vector<bool>> expected{{true, false}, {false, true}, {true}};
  EXPECT_EQ(track, expected);
}

TEST(MovingBoxes, ANonFiniteOrNegativeSpeedOrWindowIsRefused) {
  // A NaN window compares false everywhere: every box would be neither fitted nor differenced.
  const Log log = track(1.0, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(moving_boxes(log.boxes, log.poses, log.times, 0.5, nan), Error);
  EXPECT_THROW(moving_boxes(log.boxes, log.poses, log.times, 0.5, inf), Error);
  EXPECT_THROW(moving_boxes(log.boxes, log.poses, log.times, 0.5, -1.0), Error);
  EXPECT_THROW(moving_boxes(log.boxes, log.poses, log.times, nan, 1.0), Error);
  EXPECT_THROW(moving_boxes(log.boxes, log.poses, log.times, -0.5, 1.0), Error);
  EXPECT_NO_THROW(moving_boxes(log.boxes, log.poses, log.times, 0.0, 0.0));
}

// A parked scooter seen from a sensor driving at 6 m/s: its boxes in scans 0-2 follow it (the
// sensor-frame centre slides back), then scans 3 and 4 hold scan 0's box again, copied, as the
// Pandar64 street's motorcycles are. And a car ahead at the sensor's speed, the same box in
// every scan (copied forward, nothing replaced in between).
TEST(StaleCopies, ABoxCopiedFromAnOlderFrameIsNoSightingButOneCopiedForwardIs) {
  Log log = track(0.0, 0.0);  // parked: world x = 10
  log.boxes.resize(5);
  log.poses.resize(5);
  log.times.resize(5);
  log.boxes[3][0] = log.boxes[0][0];
  log.boxes[4][0] = log.boxes[0][0];
  LabelBox ahead;
  ahead.id = "9";
  ahead.centre = Eigen::Vector3d(15.0, 0.0, 0.0);
  for (auto& scan : log.boxes) scan.push_back(ahead);
  const auto stale = stale_copies(log.boxes);
  const std::vector<std::vector<bool>> expected{{false, false}, {false, false}, {false, false}, {true, false},
                                                {true, false}};
  EXPECT_EQ(stale, expected);
  // With the copies, the parked scooter jumps 1.8 m in 0.1 s at scan 3 and reads as moving
  // (the line over 1 s through world x = 10, 10, 10, 11.8, 12.4 climbs 6.6 m/s)...
  const auto all = moving_boxes(log.boxes, log.poses, log.times, 0.5, 1.0);
  EXPECT_TRUE(all[3][0]);
  // ...and on its sightings alone it stands; the car ahead moves at 6 m/s either way.
  std::vector<std::vector<LabelBox>> sightings(log.boxes.size());
  for (std::size_t i = 0; i < log.boxes.size(); ++i) {
    for (std::size_t k = 0; k < log.boxes[i].size(); ++k) {
      if (!stale[i][k]) sightings[i].push_back(log.boxes[i][k]);
    }
  }
  const auto seen = moving_boxes(sightings, log.poses, log.times, 0.5, 1.0);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_FALSE(seen[i][0]) << i;
    EXPECT_TRUE(seen[i][1]) << i;
  }
  EXPECT_TRUE(seen[3][0]);  // scans 3 and 4 kept the car ahead only
  EXPECT_TRUE(seen[4][0]);
}

// The definition, word for word: equal to an older box of its object, with some box in between
// (after that older one) not equal to it.
std::vector<std::vector<bool>> stale_by_definition(const std::vector<std::vector<LabelBox>>& boxes) {
  auto same = [](const LabelBox& a, const LabelBox& b) {
    return a.centre == b.centre && a.yaw == b.yaw && a.size == b.size;
  };
  std::vector<std::vector<bool>> stale(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (const auto& b : boxes[i]) {
      bool copy = false;
      for (std::size_t e = 0; e < i && !copy; ++e) {
        for (const auto& older : boxes[e]) {
          if (older.id != b.id || !same(older, b)) continue;
          for (std::size_t f = e + 1; f < i && !copy; ++f) {
            for (const auto& between : boxes[f]) copy = copy || (between.id == b.id && !same(between, b));
          }
        }
      }
      stale[i].push_back(copy);
    }
  }
  return stale;
}

// Random tracks drawn from three boxes per object (so copies, runs and returns abound), some
// scans without the object, a NaN now and then, -0 against +0: the one-look-up rule agrees
// with the definition on every box.
TEST(StaleCopies, AgreesWithTheDefinitionOnRandomTracks) {
  std::mt19937 rng(7);
  const double values[] = {0.0, -0.0, 1.5, std::numeric_limits<double>::quiet_NaN()};
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::vector<LabelBox>> boxes(1 + rng() % 30);
    for (auto& scan : boxes) {
      for (const char* id : {"a", "b"}) {
        if (rng() % 4 == 0) continue;
        LabelBox box;
        box.id = id;
        box.centre.x() = values[rng() % (trial % 2 ? 4 : 3)];
        box.yaw = static_cast<double>(rng() % 2);
        scan.push_back(box);
      }
    }
    EXPECT_EQ(stale_copies(boxes), stale_by_definition(boxes)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace cleanmap
