// Ground that real scans do not fool: returns from below the road, and a floor that stays the
// same across the scans that score each other.
#include <algorithm>
#include <functional>
#include <gtest/gtest.h>
#include <vector>

#include "dynamics/ground_segmentation.hpp"

namespace cleanmap {
namespace {

struct Cloud {
  std::vector<Eigen::Vector3f> pts;
  void grid(double x0, double x1, double y0, double y1, const std::function<double(double, double)>& z) {
    for (double x = x0; x < x1; x += 0.2) {
      for (double y = y0; y < y1; y += 0.2) pts.emplace_back(float(x), float(y), float(z(x, y)));
    }
  }
  Eigen::Matrix3Xf matrix() const {
    Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = pts[i];
    return m;
  }
};

// Share of the points in [first, last) labelled ground.
double ground_share(const std::vector<std::uint8_t>& g, std::size_t first, std::size_t last) {
  double n = 0;
  for (std::size_t i = first; i < last; ++i) n += g[i];
  return n / static_cast<double>(last - first);
}

TEST(GroundSegmentation, ReturnsFromBelowTheRoadDoNotSinkTheFloor) {
  // A flat road and a 0.15 m kerb, plus a mirror image in a wet patch: three returns 3.7 m
  // under the road in one cell (as on SemanticKITTI 07). The old floor (lowest point, bounded by
  // the slope envelope) sank every cell within 3 m and made the road around it non-ground.
  Cloud c;
  c.grid(-10, 10, -10, 2, [](double, double) { return 0.0; });
  c.grid(-10, 10, 2, 6, [](double, double) { return 0.15; });
  const std::size_t surface = c.pts.size();
  for (float dy : {0.0f, 0.1f, 0.2f}) c.pts.emplace_back(2.3f, -1.5f + dy, -3.7f);
  const auto g = segment_ground(c.matrix(), GroundConfig{});
  EXPECT_EQ(ground_share(g, 0, surface), 1.0);
}

TEST(GroundSegmentation, AReturnAloneInItsCellFarUnderTheRoadDoesNotLiftTheRoadAroundIt) {
  // As on KITTI 00: one return 9 m under the road in a cell the road's own returns miss (the
  // rings pass beside it). Its cell's floor was the lowest admissible level, 0.85 m under the
  // road (the block's median less a walkable slope across the block and the band), and that
  // floor was every neighbouring cell's too: the road around it lay 0.85 m above the floor.
  Cloud c;
  c.grid(-10, 10, -10, 10, [](double, double) { return 0.0; });
  const auto in_hole = [](const Eigen::Vector3f& p) { return p.x() >= 2 && p.x() < 3 && p.y() >= -2 && p.y() < -1; };
  c.pts.erase(std::remove_if(c.pts.begin(), c.pts.end(), in_hole), c.pts.end());
  const std::size_t surface = c.pts.size();
  c.pts.emplace_back(2.5f, -1.5f, -9.0f);
  const auto g = segment_ground(c.matrix(), GroundConfig{});
  EXPECT_EQ(ground_share(g, 0, surface), 1.0);
  EXPECT_EQ(g[surface], 1);  // the return itself is under the floor: not an object
  // The same with a memory: the next scan, road only, is not lowered by the remembered cell.
  GroundMemory memory;
  memory.scans = 3;
  segment_ground(c.matrix(), GroundConfig{}, &memory);
  Cloud road;
  road.grid(-10, 10, -10, 10, [](double, double) { return 0.0; });
  EXPECT_EQ(ground_share(segment_ground(road.matrix(), GroundConfig{}, &memory), 0, road.pts.size()), 1.0);
}

TEST(GroundSegmentation, AFloorDeeperThanASlopeExplainsIsStillGroundWhereItIsTheWholeBlock) {
  // A sunken yard 1.5 m below the street, 8 m wide: inside it the yard is its cells' own floor
  // (their 3x3 median), so the rule against returns from below keeps it ground.
  Cloud c;
  c.grid(-10, 10, -10, 10, [](double x, double y) { return std::abs(x) < 4 && std::abs(y) < 4 ? -1.5 : 0.0; });
  const auto m = c.matrix();
  const auto g = segment_ground(m, GroundConfig{});
  std::size_t yard = 0, yard_ground = 0;
  for (Eigen::Index i = 0; i < m.cols(); ++i) {
    if (std::abs(m(0, i)) < 2.5 && std::abs(m(1, i)) < 2.5) {
      ++yard;
      yard_ground += g[static_cast<std::size_t>(i)];
    }
  }
  ASSERT_GT(yard, 0u);
  EXPECT_EQ(yard_ground, yard);
}

// A pavement 0.3 m above the road beside it. `road` says whether this scan sees the road (the
// parked cars hide it in the next).
Cloud street(bool road) {
  Cloud c;
  if (road) c.grid(-10, 10, -6, 0, [](double, double) { return 0.0; });
  c.grid(-10, 10, 0, 6, [](double, double) { return 0.3; });
  return c;
}

// Ground share of the pavement's first metre beside the kerb.
double kerb_share(const Cloud& c, const std::vector<std::uint8_t>& g) {
  double n = 0, k = 0;
  for (std::size_t i = 0; i < c.pts.size(); ++i) {
    if (c.pts[i].y() >= 0 && c.pts[i].y() < 1) {
      ++n;
      k += g[i];
    }
  }
  return k / n;
}

TEST(GroundSegmentation, TheMemoryKeepsOneFloorAcrossScansThatSeeDifferentParts) {
  const GroundConfig config;
  const Cloud seen = street(true), hidden = street(false);
  // Alone, the two scans disagree on the pavement beside the kerb: a floor 0.3 m lower in the
  // 3x3 block in one, none in the other.
  EXPECT_EQ(kerb_share(seen, segment_ground(seen.matrix(), config)), 0.0);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config)), 1.0);
  // With a memory of 3 scans the second scan takes the first's floor, until it is forgotten.
  GroundMemory memory;
  memory.scans = 3;
  EXPECT_EQ(kerb_share(seen, segment_ground(seen.matrix(), config, &memory)), 0.0);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 0.0);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 0.0);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 1.0);
  EXPECT_EQ(memory.now, 4u);
}

TEST(GroundSegmentation, TheMemoryForgetsALowerFloorOnlyWhenItAges) {
  // The remembered floor is the lowest of the span, not the last one seen: a scan that sees the
  // road again renews it.
  const GroundConfig config;
  const Cloud seen = street(true), hidden = street(false);
  GroundMemory memory;
  memory.scans = 2;
  segment_ground(seen.matrix(), config, &memory);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 0.0);
  segment_ground(seen.matrix(), config, &memory);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 0.0);
  EXPECT_EQ(kerb_share(hidden, segment_ground(hidden.matrix(), config, &memory)), 1.0);
}

TEST(GroundSegmentation, AMirrorImageRememberedFromOneScanDoesNotSinkTheNextScansFloor) {
  // A mirror image 3.7 m under the road, 2.4 m across: it fills the whole 3x3 block of the cells
  // in its middle, so the scan that holds it takes it for their floor (their block's median is
  // the image). On the Pandar64 street such an image, remembered for the scorer's 11 scans,
  // made a 3 x 4 m patch of road non-ground in the scans after it, and the tracker followed the
  // patch as an object (8 k false dynamic points). The next scans see the road there: a
  // remembered floor further under their own block's floor than a slope and the band explain
  // is the image again, and is forgotten.
  Cloud road;
  road.grid(-10, 10, -10, 10, [](double, double) { return 0.0; });
  Cloud mirrored = road;
  const std::size_t surface = mirrored.pts.size();
  mirrored.grid(2.0, 4.4, -2.0, 0.4, [](double, double) { return -3.7; });
  const GroundConfig config;
  EXPECT_LT(ground_share(segment_ground(mirrored.matrix(), config), 0, surface), 1.0);
  GroundMemory memory;
  memory.scans = 3;
  segment_ground(mirrored.matrix(), config, &memory);
  const auto next = segment_ground(road.matrix(), config, &memory);
  EXPECT_EQ(ground_share(next, 0, road.pts.size()), 1.0);
  // Forgotten, not just passed over: the scan after sees the road as ground too.
  EXPECT_EQ(ground_share(segment_ground(road.matrix(), config, &memory), 0, road.pts.size()), 1.0);
}

// A car's side far off (two rings at z 0.3 and 0.5 over x in [30, 34), y = 5), with no road
// within `reach` of it in its own scan: the road beside and behind it is hidden or between
// rings. Its lower ring is its cells' floor, so both rings are ground.
Cloud far_car() {
  Cloud c;
  for (double x = 30.0; x < 34.0; x += 0.1) {
    c.pts.emplace_back(float(x), 5.0f, 0.3f);
    c.pts.emplace_back(float(x), 5.0f, 0.5f);
  }
  return c;
}

TEST(GroundSegmentation, TheLogsFloorUnderACarThatDroveOnLiftsItOffTheGround) {
  const GroundConfig config;
  const Cloud car = far_car();
  EXPECT_EQ(ground_share(segment_ground(car.matrix(), config), 0, car.pts.size()), 1.0);
  // Another scan saw the road there (z = 0) once the car had gone: over the log, the lowest
  // point of those cells is the road's, and both rings stand 0.3 and 0.5 m above it.
  Cloud road;
  road.grid(28, 36, 3, 7, [](double, double) { return 0.0; });
  LogFloor floor;
  add_to_floor(car.matrix(), config, floor);
  add_to_floor(road.matrix(), config, floor);
  ASSERT_EQ(floor.at(VoxelKey{31, 5, 0}), 0.0f);
  EXPECT_EQ(ground_share(segment_ground(car.matrix(), config, floor), 0, car.pts.size()), 0.0);
  // The log's floor is read, never written: segmenting the car's scan left the cell's floor
  // at the road's height, not the sill's.
  EXPECT_EQ(floor.at(VoxelKey{31, 5, 0}), 0.0f);
}

TEST(GroundSegmentation, TheLogsFloorDoesNotSinkACellDeeperThanASlopeExplains) {
  // A mirror image 3.7 m down that filled its scan's whole block is that scan's floor there;
  // under this scan's own floor it is deeper than a slope and the band explain (0.85 m under
  // the block's median with the defaults), and the car stays on its own floor.
  const GroundConfig config;
  const Cloud car = far_car();
  Cloud image;
  image.grid(28, 36, 3, 7, [](double, double) { return -3.7; });
  LogFloor floor;
  add_to_floor(image.matrix(), config, floor);
  ASSERT_EQ(floor.at(VoxelKey{31, 5, 0}), -3.7f);
  EXPECT_EQ(ground_share(segment_ground(car.matrix(), config, floor), 0, car.pts.size()), 1.0);
}

TEST(GroundSegmentation, AScanThatSawItsOwnRoadIsSegmentedAsWithoutTheLogsFloor) {
  // A static street: the log's floor of the scan itself changes nothing.
  Cloud street;
  street.grid(-10, 10, -10, 10, [](double x, double) { return 0.05 * x; });
  street.grid(2, 4, 2, 3, [](double, double) { return 1.2; });  // a car's roof
  const GroundConfig config;
  LogFloor floor;
  add_to_floor(street.matrix(), config, floor);
  EXPECT_EQ(segment_ground(street.matrix(), config, floor),
            segment_ground(street.matrix(), config));
}

}  // namespace
}  // namespace cleanmap
