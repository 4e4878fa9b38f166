#include "dynamics/euclidean_clusters.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace cleanmap {
namespace {

// True when a and b put the same points together and leave the same points out (ids may be
// numbered differently).
bool same_partition(const std::vector<std::int32_t>& a, const std::vector<std::int32_t>& b) {
  if (a.size() != b.size()) return false;
  std::map<std::int32_t, std::int32_t> ab, ba;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i] < 0) != (b[i] < 0)) return false;
    if (a[i] < 0) continue;
    const auto [x, fresh_x] = ab.emplace(a[i], b[i]);
    const auto [y, fresh_y] = ba.emplace(b[i], a[i]);
    if (x->second != b[i] || y->second != a[i]) return false;
  }
  return true;
}

// Blobs of dense points (2 cm apart, within 0.1 m of their centres) along x. Between
// neighbours the gap is either none (they touch) or wider than the radius plus a voxel
// diagonal on each side: on both sides of that bound the subsample must link exactly what the
// full-resolution clustering links.
TEST(ClustersOnVoxels, AgreeWithFullResolutionWhereGapsAreClearOfTheVoxels) {
  const float radius = 0.6f;
  const double voxel = radius / 2.0;
  const double wide = radius + 2 * std::sqrt(3.0) * voxel + 0.1;  // 1.74 m
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Eigen::Vector3f> pts;
    double x = 0;
    const int blobs = 2 + trial % 6;
    for (int b = 0; b < blobs; ++b) {
      for (int k = 0; k < 60; ++k) pts.emplace_back(x + jitter(rng), jitter(rng), 1.0f + jitter(rng));
      x += (rng() % 2) ? 0.15 : wide + 0.2;  // touching (blobs are 0.2 m wide) or apart
    }
    std::shuffle(pts.begin(), pts.end(), rng);
    Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = pts[i];
    std::vector<std::uint8_t> include(pts.size()), seed(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      include[i] = rng() % 10 != 0;  // a tenth left out
      seed[i] = rng() % 40 == 0;     // some blobs hold no seed
    }
    const auto full = clusters_from_seeds(m, include, seed, radius);
    const auto sub = clusters_on_voxels(m, include, seed, radius, voxel);
    EXPECT_TRUE(same_partition(full, sub)) << "trial " << trial;
  }
}

TEST(ClustersOnVoxels, LeavesOutExcludedAndSeedlessPointsAndNumbersFromZero) {
  Eigen::Matrix3Xf m(3, 6);
  m << 0, 0.05f, 0.1f, 5, 5.05f, 0.02f,  //
      0, 0, 0, 0, 0, 0,                  //
      0, 0, 0, 0, 0, 0;
  const std::vector<std::uint8_t> include{1, 1, 1, 1, 1, 0}, seed{0, 0, 0, 1, 0, 1};
  const auto id = clusters_on_voxels(m, include, seed, 0.6f, 0.3);
  // Points 0-2 have no seed (5 is a seed but left out); 3 and 4 are one cluster, id 0.
  EXPECT_EQ(id, (std::vector<std::int32_t>{-1, -1, -1, 0, 0, -1}));
  EXPECT_EQ(clusters_on_voxels(m, std::vector<std::uint8_t>(6, 0), seed, 0.6f, 0.3),
            std::vector<std::int32_t>(6, -1));
}

}  // namespace
}  // namespace cleanmap
