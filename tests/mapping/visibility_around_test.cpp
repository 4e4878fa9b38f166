// The visibility of a few cells from the rays that can reach them (mapping/visibility_around)
// against the map of every hit and ray.
#include "mapping/visibility_around.hpp"

#include <gtest/gtest.h>

#include <random>

namespace cleanmap {
namespace {

// A street seen from a sensor driving along x: a wall on each side, a floor, and a box that
// stands at x = 8 for the first `box_scans` scans (then gone: rays reach the wall behind it).
Eigen::Matrix3Xf street_scan(const Eigen::Vector3d& origin, bool box, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < 6000; ++i) {
    const float x = static_cast<float>(origin.x()) - 10.0f + 30.0f * u(rng), z = 3.0f * u(rng);
    p.emplace_back(x, i % 2 ? 6.0f : -6.0f, z);  // the walls
    p.emplace_back(x, -6.0f + 12.0f * u(rng), 0.0f);  // the floor
  }
  if (box) {
    for (int i = 0; i < 800; ++i) p.emplace_back(8.0f + u(rng), -4.0f + u(rng), 1.5f * u(rng));
  }
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

TEST(VisibilityAround, CountsTheCellsOfInterestAsTheWholeMapDoes) {
  std::mt19937 rng(3);
  std::vector<Eigen::Matrix3Xf> scans;
  std::vector<ScanView> views;
  for (int s = 0; s < 9; ++s) {
    const Eigen::Vector3d origin(0.5 * s, 0.0, 1.7);
    scans.push_back(street_scan(origin, s < 4, rng));
  }
  for (int s = 0; s < 9; ++s) {
    const Eigen::Vector3d origin(0.5 * s, 0.0, 1.7);
    views.push_back({&scans[static_cast<std::size_t>(s)], nullptr, origin, SweepOrigin{origin}});
  }
  VisibilityConfig config;
  VisibilityMap full(config);
  for (const auto& v : views) full.add_hits(*v.points, v.origin);
  for (const auto& v : views) full.add_rays(*v.points, v.origin);
  // Of interest: the box as scan 0 saw it, and a patch of the far wall.
  std::vector<Eigen::Index> pick;
  for (Eigen::Index i = 0; i < scans[0].cols(); ++i) {
    const Eigen::Vector3f q = scans[0].col(i);
    if (q.x() >= 8.0f && q.x() < 9.0f && q.y() < -3.0f) pick.push_back(i);
  }
  const Eigen::Matrix3Xf around = scans[0](Eigen::all, pick);
  ASSERT_GT(around.cols(), 800);
  const VisibilityMap part = visibility_around(around, views, config);
  EXPECT_EQ(part.cells(), full.cells());  // every hit
  std::size_t box_through = 0, differ = 0;
  for (Eigen::Index i = 0; i < around.cols(); ++i) {
    const auto a = full.counts(around.col(i)), b = part.counts(around.col(i));
    ASSERT_EQ(a.hits, b.hits) << i;
    ASSERT_EQ(a.first_hit, b.first_hit) << i;
    ASSERT_EQ(a.last_hit, b.last_hit) << i;
    // The whole map stops walking a ray where the scan's earlier rays walked on (carve_ray),
    // at times before a cell it would have crossed; without those rays the walk goes on.
    ASSERT_GE(b.crossed, a.crossed) << i;
    ASSERT_GE(b.through, a.through) << i;
    ASSERT_GE(b.through_apart, a.through_apart) << i;
    differ += a.crossed != b.crossed || a.through != b.through;
    box_through += around(1, i) > -4.0f ? a.through : 0;
  }
  EXPECT_EQ(differ, 0u);  // here, no walk stopped before a cell of interest
  EXPECT_GT(box_through, 0u);  // the scans after the box went through its cells
}

}  // namespace
}  // namespace cleanmap
