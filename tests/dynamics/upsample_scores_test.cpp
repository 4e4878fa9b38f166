#include "dynamics/upsample_scores.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "geometry/voxel_downsample.hpp"

namespace cleanmap {
namespace {

TEST(UpsampleScores, PaperRuleMatchesABruteForceSearchAndScoresByVoxel) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-6.0f, 6.0f);
  Eigen::Matrix3Xf full(3, 20000);
  for (Eigen::Index i = 0; i < full.cols(); ++i) full.col(i) = Eigen::Vector3f(u(rng), u(rng), u(rng) / 4);
  const double voxel = 0.4, radius = 0.5;
  const auto sample = voxel_downsample_with_owners(full, voxel);
  Eigen::Matrix3Xf down(3, static_cast<Eigen::Index>(sample.keep.size()));
  PointDecisions d;
  for (std::size_t k = 0; k < sample.keep.size(); ++k) {
    down.col(static_cast<Eigen::Index>(k)) = full.col(sample.keep[k]);
    d.score.push_back(k % 7 == 0 ? std::nanf("") : static_cast<float>(k % 100) / 100.0f);
    d.dynamic.push_back(k % 37 == 0 ? 1 : 0);
  }
  const auto out = upsample_scores(full, down, sample.owner, d, "paper", radius);
  std::size_t dynamic = 0;
  for (Eigen::Index i = 0; i < full.cols(); ++i) {
    const auto s = static_cast<std::size_t>(i);
    // Every point lies in the voxel of the point that stands for it.
    const auto o = static_cast<std::size_t>(sample.owner[s]);
    EXPECT_EQ(((full.col(i) / voxel).array().floor() - (down.col(sample.owner[s]) / voxel).array().floor()).abs().sum(), 0.0f);
    if (std::isnan(d.score[o])) EXPECT_TRUE(std::isnan(out.score[s]));
    else EXPECT_EQ(out.score[s], d.score[o]);
    bool near = false;
    for (Eigen::Index k = 0; k < down.cols(); ++k) {
      near = near || (d.dynamic[static_cast<std::size_t>(k)] && (down.col(k) - full.col(i)).squaredNorm() <= radius * radius);
    }
    EXPECT_EQ(out.dynamic[s], near ? 1 : 0) << "point " << i;
    dynamic += out.dynamic[s];
  }
  EXPECT_GT(dynamic, 500u);  // the test exercises both answers
  EXPECT_LT(dynamic, 15000u);
}

TEST(UpsampleScores, NearestRuleTakesTheNearestWithinTheRadius) {
  Eigen::Matrix3Xf down(3, 2);
  down << 0, 1, 0, 0, 0, 0;
  PointDecisions d{{0.1f, 0.9f}, {0, 1}};
  Eigen::Matrix3Xf full(3, 3);
  full << 0.2f, 0.8f, 3.0f, 0, 0, 0, 0, 0, 0;
  const auto out = upsample_scores(full, down, {}, d, "nearest", 0.5);
  EXPECT_FLOAT_EQ(out.score[0], 0.1f);
  EXPECT_EQ(out.dynamic[0], 0);
  EXPECT_FLOAT_EQ(out.score[1], 0.9f);
  EXPECT_EQ(out.dynamic[1], 1);
  EXPECT_TRUE(std::isnan(out.score[2]));  // nothing within the radius
}

// The voxel grid's nearest neighbour is the brute-force one, at every distance: points on a
// surface (many share a voxel) and scattered ones (mostly alone), negative coordinates too.
TEST(UpsampleScores, NearestOnVoxelsIsTheBruteForceNearest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  Eigen::Matrix3Xf full(3, 6000);
  for (Eigen::Index i = 0; i < full.cols(); ++i) {
    const float z = i % 2 ? u(rng) : 0.05f * u(rng);
    full.col(i) = Eigen::Vector3f(u(rng), u(rng), z);
  }
  for (const double voxel : {0.1, 0.37}) {
    const auto sample = voxel_downsample_with_owners(full, voxel);
    Eigen::Matrix3Xf down = full(Eigen::all, sample.keep);
    const auto nn = nearest_on_voxels(full, down, sample.owner, voxel);
    std::size_t moved = 0;
    for (Eigen::Index i = 0; i < full.cols(); ++i) {
      float best = std::numeric_limits<float>::infinity();
      for (Eigen::Index k = 0; k < down.cols(); ++k)
        best = std::min(best, (down.col(k) - full.col(i)).squaredNorm());
      const auto s = static_cast<std::size_t>(i);
      EXPECT_EQ((down.col(nn[s]) - full.col(i)).squaredNorm(), best)
          << "point " << i << ", voxel " << voxel;
      moved += nn[s] != sample.owner[s];
    }
    EXPECT_GT(moved, 30u);  // the owner is often not the nearest: the search is exercised
  }
}

TEST(UpsampleScores, PointsOnTheFloorKeepTheirOwnDecision) {
  // A dynamic tyre edge (downsampled point 0) 0.1 m from a road point (1): the paper's radius
  // paints the road too, unless the road is marked as keeping its own decision.
  Eigen::Matrix3Xf down(3, 2), full(3, 2);
  down << 0, 0.1f, 0, 0, 0.15f, 0.0f;
  full = down;
  const std::vector<std::int32_t> owner{0, 1};
  PointDecisions d{{0.9f, 0.0f}, {1, 0}};
  EXPECT_EQ(upsample_scores(full, down, owner, d, "paper", 0.3).dynamic, (std::vector<std::uint8_t>{1, 1}));
  EXPECT_EQ(upsample_scores(full, down, owner, d, "paper", 0.3, {0, 1}).dynamic, (std::vector<std::uint8_t>{1, 0}));
  // A dynamic point on the floor keeps that too.
  EXPECT_EQ(upsample_scores(full, down, owner, d, "paper", 0.3, {1, 1}).dynamic, (std::vector<std::uint8_t>{1, 0}));
}

}  // namespace
}  // namespace cleanmap
