// The scorer's blocked cell table against a plain map of the same operations: every cell's
// moments, what exists and what was dropped, across block boundaries and negative keys.
#include <gtest/gtest.h>

#include <random>

#include "dynamics/cell_table.hpp"

namespace cleanmap {
namespace {

Moments4 one_point(double x, double t) {
  Moments4 m;
  m.add(Eigen::Vector4d(x, 2 * x, -x, t));
  return m;
}

TEST(CellTable, MatchesAPlainMapThroughAddsAndSubtracts) {
  CellTable table;
  tsl::robin_map<VoxelKey, std::pair<Moments4, int>, VoxelKeyHash> truth;  // moments, points
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(-6, 6);  // blocks of 4 cells: -8..-5, -4..-1, 0..3, 4..7
  std::vector<std::pair<VoxelKey, Moments4>> added;
  for (int step = 0; step < 4000; ++step) {
    if (added.empty() || rng() % 3 != 0) {
      const VoxelKey k{coord(rng), coord(rng), coord(rng)};
      const Moments4 m = one_point(0.01 * step, 0.1 * step);
      table.add(k, m);
      auto& [sum, count] = truth[k];
      sum += m;
      ++count;
      added.emplace_back(k, m);
    } else {  // take back one earlier point, as the window drops a scan
      const std::size_t i = rng() % added.size();
      const auto [k, m] = added[i];
      added.erase(added.begin() + static_cast<std::ptrdiff_t>(i));
      table.subtract(k, m);
      auto it = truth.find(k);
      it.value().first -= m;
      if (--it.value().second == 0) truth.erase(it);
    }
  }
  EXPECT_EQ(table.size(), truth.size());
  for (int x = -7; x <= 7; ++x) {
    for (int y = -7; y <= 7; ++y) {
      for (int z = -7; z <= 7; ++z) {
        const VoxelKey k{x, y, z};
        const Moments4* got = table.find(k);
        const auto it = truth.find(k);
        ASSERT_EQ(got != nullptr, it != truth.end()) << x << " " << y << " " << z;
        if (!got) continue;
        EXPECT_NEAR(got->n, it->second.first.n, 1e-9);
        EXPECT_NEAR((got->sum - it->second.first.sum).norm(), 0.0, 1e-6);
        EXPECT_NEAR((got->sum_sq() - it->second.first.sum_sq()).norm(), 0.0, 1e-6);
      }
    }
  }
}

TEST(CellTable, AnEmptiedCellAndBlockAreGoneAndTheirSpaceIsReused) {
  CellTable table;
  const VoxelKey a{-1, -1, -1}, b{0, 0, 0};  // neighbours in two different blocks
  table.add(a, one_point(1, 0));
  table.add(b, one_point(2, 0));
  EXPECT_EQ(table.size(), 2u);
  table.subtract(a, one_point(1, 0));
  EXPECT_EQ(table.find(a), nullptr);
  ASSERT_NE(table.find(b), nullptr);
  EXPECT_DOUBLE_EQ(table.find(b)->n, 1.0);
  table.subtract(VoxelKey{40, 40, 40}, one_point(1, 0));  // never added: nothing happens
  EXPECT_EQ(table.size(), 1u);
  table.add(VoxelKey{-5, -5, -5}, one_point(3, 0));  // a fresh block takes the emptied one's row
  EXPECT_EQ(table.find(a), nullptr);
  ASSERT_NE(table.find(VoxelKey{-5, -5, -5}), nullptr);
  EXPECT_DOUBLE_EQ(table.find(VoxelKey{-5, -5, -5})->sum[0], 3.0);
  EXPECT_EQ(table.size(), 2u);
}

}  // namespace
}  // namespace cleanmap
