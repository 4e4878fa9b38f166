// Which way a line of hits faces, from the cells around it, and the side it was seen from: the
// rules that tell a ray over a roof's ring from one between the rows of a car's side.
#include <gtest/gtest.h>

#include <vector>

#include "mapping/visibility_map.hpp"

namespace cleanmap {
namespace {

Eigen::Matrix3Xf cloud(const std::vector<Eigen::Vector3f>& p) {
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

// A flat roof at z = 1.5 seen as three rings: lines along y at x = 5.05, 5.25, 5.45 (one per
// 0.2 m cell along x), y in [0, 0.6). Each cell holds one line: thin along x and z.
Eigen::Matrix3Xf roof_rings() {
  std::vector<Eigen::Vector3f> p;
  for (const float x : {5.05f, 5.25f, 5.45f}) {
    for (int i = 0; i < 30; ++i) p.emplace_back(x, 0.01f + 0.02f * static_cast<float>(i), 1.5f);
  }
  return cloud(p);
}

const Eigen::Vector3f kRoofCell(5.25f, 0.3f, 1.5f);  // the middle ring's middle cell

// The wall at x = 9.1 that rays at height z reach, from x = 0.1.
double crossings_at(VisibilityMap& map, float z) {
  const Eigen::Matrix3Xf wall = cloud({{9.1f, 0.3f, z}});
  map.add_hits(wall);
  map.add_rays(wall, Eigen::Vector3d(0.1, 0.3, z));
  return map.counts(kRoofCell).crossed;
}

TEST(VisibilityFaces, ARayOverARoofsRingsDoesNotCrossThem) {
  // The sensor above the roof (1.8 m) hit it; a later ray passes 8 cm over it (beyond the 5 cm
  // extent margin). Alone, the ring's cell is thin along x as well, and the ray reaches its x
  // level: that counted as seeing through it. Its neighbours are at its z level in two
  // directions, so z is the axis it faces, and the ray over the roof does not cross it.
  VisibilityMap map{VisibilityConfig{}};
  map.add_hits(roof_rings(), Eigen::Vector3d(0.1, 0.3, 1.8));
  map.fit_surfaces();
  EXPECT_EQ(map.counts(kRoofCell).faces, 1 << 2);
  EXPECT_EQ(crossings_at(map, 1.58f), 0);
}

TEST(VisibilityFaces, ARayUnderARoofsLevelCrossesWhatWasBeneathIt) {
  // 8 cm under the roof's level, inside what the sensor above it hit (a car's body): that ray
  // went through the car, and counts. Hits seen from no known side count only at their level.
  for (const bool seen_from_above : {true, false}) {
    VisibilityMap map{VisibilityConfig{}};
    if (seen_from_above) {
      map.add_hits(roof_rings(), Eigen::Vector3d(0.1, 0.3, 1.8));
    } else {
      map.add_hits(roof_rings());
    }
    EXPECT_EQ(crossings_at(map, 1.42f), seen_from_above ? 1 : 0) << seen_from_above;
  }
}

// A car's side at y = 0.1 seen as three rows (z = 1.3, 1.5, 1.7, one per cell), x in
// [5.0, 5.6): each cell holds one row, thin along y and z.
Eigen::Matrix3Xf side_rows() {
  std::vector<Eigen::Vector3f> p;
  for (const float z : {1.3f, 1.5f, 1.7f}) {
    for (int i = 0; i < 30; ++i) p.emplace_back(5.01f + 0.02f * static_cast<float>(i), 0.1f, z);
  }
  return cloud(p);
}

TEST(VisibilityFaces, ARayBetweenTheRowsOfASideCrossesItAndOneInFrontDoesNot) {
  // The rows above and below are at its y level: the side faces y, and a ray through it 8 cm
  // above a row (between two rows) crosses it; a ray along the side, 8 cm in front of it
  // (the sensor's side), does not.
  const Eigen::Vector3f cell(5.3f, 0.1f, 1.5f);
  VisibilityMap map{VisibilityConfig{}};
  map.add_hits(side_rows(), Eigen::Vector3d(5.3, -8.0, 1.5));
  const Eigen::Matrix3Xf far = cloud({{5.3f, 9.0f, 1.58f}}), along = cloud({{9.1f, 0.02f, 1.58f}});
  map.add_hits(far);
  map.add_hits(along);
  map.fit_surfaces();
  EXPECT_EQ(map.counts(cell).faces, 1 << 1);
  map.add_rays(along, Eigen::Vector3d(0.1, 0.02, 1.58));
  EXPECT_EQ(map.counts(cell).crossed, 0);
  map.add_rays(far, Eigen::Vector3d(5.3, -8.0, 1.58));
  EXPECT_EQ(map.counts(cell).crossed, 1);
}

TEST(VisibilityFaces, CastingBeforeTheFacesAreFittedIsRefused) {
  VisibilityMap map{VisibilityConfig{}};
  map.add_hits(side_rows());
  EXPECT_THROW(map.cast(side_rows(), Eigen::Vector3d::Zero()), std::logic_error);
  map.fit_surfaces();
  EXPECT_NO_THROW(map.cast(side_rows(), Eigen::Vector3d::Zero()));
}

}  // namespace
}  // namespace cleanmap
