#include "odometry/platform_mask.hpp"

#include <random>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// A sensor driving along x over a field of world points: a mount bracket 1 m behind it stays
// put in the sensor frame, the world slides past.
std::vector<Eigen::Matrix3Xf> driving_scans(double step) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-4.f, 4.f);
  Eigen::Matrix3Xf world(3, 4000);
  for (Eigen::Index i = 0; i < world.cols(); ++i) world.col(i) = Eigen::Vector3f(u(rng) * 10, u(rng), u(rng) * 0.5f);
  std::vector<Eigen::Matrix3Xf> scans;
  for (int k = 0; k < 10; ++k) {
    Eigen::Matrix3Xf s(3, world.cols() + 50);
    s.leftCols(world.cols()) = world.colwise() - Eigen::Vector3f(static_cast<float>(step * k), 0, 0);
    for (int j = 0; j < 50; ++j) s.col(world.cols() + j) = Eigen::Vector3f(-1.0f, 0.01f * j, -0.3f);
    scans.push_back(s);
  }
  return scans;
}

TEST(PlatformMask, PointsFixedInTheSensorFrameAreMaskedWhenTheSensorMoves) {
  const auto scans = driving_scans(0.7);
  const auto mask = learn_platform_mask(scans, PlatformMaskConfig{});
  EXPECT_TRUE(mask.note.empty()) << mask.note;
  EXPECT_TRUE(mask.contains(Eigen::Vector3f(-1.0f, 0.2f, -0.3f)));
  const auto keep = unmasked_points(scans[5], mask);
  // Every bracket point goes; of the world, at most what happens to fall in its cells.
  std::size_t bracket_kept = 0;
  for (auto i : keep) bracket_kept += i >= 4000;
  EXPECT_EQ(bracket_kept, 0u);
  EXPECT_GT(keep.size(), 3950u);
}

TEST(PlatformMask, AStillSensorLearnsNothingAndSaysWhy) {
  const auto scans = driving_scans(0.0);
  const auto mask = learn_platform_mask(scans, PlatformMaskConfig{});
  EXPECT_TRUE(mask.cells.empty());
  EXPECT_NE(mask.note.find("did not move"), std::string::npos) << mask.note;
  EXPECT_EQ(unmasked_points(scans[0], mask).size(), static_cast<std::size_t>(scans[0].cols()));
}

TEST(PlatformMask, CropBoxMasksItsPointsAndBadBoxesAreRejected) {
  PlatformMaskConfig cfg;
  cfg.automatic = false;
  cfg.crop_box = {-2, -1, -1, 0.5, 1, 0};
  validate(cfg);
  const auto mask = learn_platform_mask({}, cfg);
  EXPECT_TRUE(mask.contains(Eigen::Vector3f(-1.f, 0.f, -0.5f)));
  EXPECT_FALSE(mask.contains(Eigen::Vector3f(1.f, 0.f, -0.5f)));
  cfg.crop_box = {0, 0, 0, 1, 1};
  test::expect_error([&] { validate(cfg); }, {"crop_box", "6 numbers"});
  cfg.crop_box = {0, 0, 0, 1, -1, 1};
  test::expect_error([&] { validate(cfg); }, {"crop_box", "minima below"});
}

}  // namespace
}  // namespace cleanmap
