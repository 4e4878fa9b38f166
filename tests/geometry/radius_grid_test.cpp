#include "geometry/radius_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>

#include "geometry/point_index.hpp"

namespace cleanmap {
namespace {

using Found = std::vector<std::pair<std::uint32_t, float>>;

Found sorted(Found f) {
  std::sort(f.begin(), f.end());
  return f;
}

// Every member strictly within the radius, by the definition (float sums as nanoflann's).
Found brute_force(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& members,
                  const Eigen::Vector3f& q, float radius) {
  Found out;
  for (std::size_t m = 0; m < members.size(); ++m) {
    float dist = 0.0f;
    for (int d = 0; d < 3; ++d) {
      const float diff = q[d] - points(d, members[m]);
      dist += diff * diff;
    }
    if (dist < radius * radius) out.emplace_back(static_cast<std::uint32_t>(m), dist);
  }
  return out;
}

TEST(RadiusGrid, FindsExactlyThePointsWithinTheRadiusAsTheKdTreeDoes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-6.0f, 6.0f);
  Eigen::Matrix3Xf points(3, 4000);
  for (Eigen::Index i = 0; i < points.cols(); ++i) points.col(i) = Eigen::Vector3f(u(rng), u(rng), u(rng) / 4);
  // Points on a cube border and at exactly the radius from a query (the strict bound).
  points.col(0) = Eigen::Vector3f(0.6f, 0.0f, 0.0f);
  points.col(1) = Eigen::Vector3f(1.2f, 0.0f, 0.0f);
  points.col(2) = Eigen::Vector3f(-0.6f, 0.0f, 0.0f);
  std::vector<std::int32_t> members;  // every third point: positions in members are reported
  for (std::int32_t i = 0; i < points.cols(); i += 3) members.push_back(i);
  const Eigen::Matrix3Xf subset = points(Eigen::all, members);
  for (const float radius : {0.15f, 0.6f, 2.5f}) {
    const RadiusGrid grid(points, members, radius);
    const PointIndex tree(subset);
    for (std::int32_t j = 0; j < points.cols(); j += 7) {
      const Eigen::Vector3f q = points.col(j);
      Found from_grid, from_tree;
      grid.for_each_within(q, [&](std::uint32_t m, float d) { from_grid.emplace_back(m, d); });
      tree.for_each_within(q, radius, [&](std::uint32_t m, float d) { from_tree.emplace_back(m, d); });
      const Found expected = brute_force(points, members, q, radius);
      ASSERT_EQ(sorted(from_grid), sorted(expected)) << "radius " << radius << " query " << j;
      ASSERT_EQ(sorted(from_tree), sorted(expected)) << "radius " << radius << " query " << j;
    }
  }
  // At 0.6 m, points 0 and 1 are exactly a radius apart, so neither finds the other.
  const RadiusGrid grid(points, {0, 1, 2}, 0.6f);
  Found near_zero;
  grid.for_each_within(points.col(0), [&](std::uint32_t m, float d) { near_zero.emplace_back(m, d); });
  EXPECT_EQ(near_zero, (Found{{0, 0.0f}}));
}

TEST(RadiusGrid, EmptyMembers) {
  const Eigen::Matrix3Xf points = Eigen::Matrix3Xf::Random(3, 10);
  const RadiusGrid grid(points, {}, 1.0f);
  int calls = 0;
  grid.for_each_within(Eigen::Vector3f::Zero(), [&](std::uint32_t, float) { ++calls; });
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace cleanmap
