#include "geometry/voxel_downsample.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

namespace cleanmap {
namespace {

// The definition, by a plain ordered map: the first point of each voxel stands for it.
VoxelSample reference(const Eigen::Matrix3Xf& points, double voxel) {
  std::map<std::tuple<long, long, long>, std::int32_t> slot;
  VoxelSample out;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const auto key = std::make_tuple(static_cast<long>(std::floor(points(0, i) / voxel)),
                                     static_cast<long>(std::floor(points(1, i) / voxel)),
                                     static_cast<long>(std::floor(points(2, i) / voxel)));
    const auto [it, fresh] = slot.emplace(key, static_cast<std::int32_t>(out.keep.size()));
    if (fresh) out.keep.push_back(static_cast<std::int32_t>(i));
    out.owner.push_back(it->second);
  }
  return out;
}

Eigen::Matrix3Xf random_cloud(int n, float extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  Eigen::Matrix3Xf p(3, n);
  for (int i = 0; i < n; ++i) p.col(i) = Eigen::Vector3f(u(rng), u(rng), u(rng) / 10);
  return p;
}

TEST(VoxelDownsample, KeepsTheFirstPointOfEachVoxelAndKnowsEveryPointsOwner) {
  for (const double voxel : {0.05, 0.3, 1.5}) {
    const auto points = random_cloud(30000, 20.0f, 3);
    const auto expected = reference(points, voxel);
    const auto got = voxel_downsample_with_owners(points, voxel);
    EXPECT_EQ(got.keep, expected.keep) << voxel;
    EXPECT_EQ(got.owner, expected.owner) << voxel;
    EXPECT_EQ(voxel_downsample(points, voxel), expected.keep) << voxel;
  }
}

TEST(VoxelDownsample, HugeExtentsAtAFineVoxel) {
  // 4e5 m across at 1 mm: 29 bits per axis, more than one 64-bit key holds.
  auto points = random_cloud(2000, 2e5f, 5);
  points.row(2) *= 10.0f;
  points.col(7) = points.col(3);  // a shared voxel
  const auto expected = reference(points, 0.001);
  const auto got = voxel_downsample_with_owners(points, 0.001);
  EXPECT_EQ(got.keep, expected.keep);
  EXPECT_EQ(got.owner, expected.owner);
  EXPECT_EQ(got.owner[7], got.owner[3]);
}

TEST(VoxelDownsample, EmptyAndSinglePointClouds) {
  EXPECT_TRUE(voxel_downsample(Eigen::Matrix3Xf(3, 0), 0.1).empty());
  Eigen::Matrix3Xf one(3, 1);
  one << -3.2f, 7.1f, 0.4f;
  const auto s = voxel_downsample_with_owners(one, 0.1);
  EXPECT_EQ(s.keep, std::vector<std::int32_t>{0});
  EXPECT_EQ(s.owner, std::vector<std::int32_t>{0});
}

}  // namespace
}  // namespace cleanmap
