#include "io/label_file.hpp"

#include <cmath>

#include "io/error.hpp"
#include "io/pose_file.hpp"
#include "io/score_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

TEST(LabelFile, RoundTripsAndSplitsClassAndInstance) {
  test::TempDir dir;
  const std::vector<std::uint32_t> labels{kLabelStatic, kLabelMoving | (7u << 16), 255u, 10u, 0u};
  write_labels(dir / "000001.label", labels);
  const auto r = read_labels(dir / "000001.label", labels.size());
  EXPECT_EQ(r, labels);
  EXPECT_EQ(semantic_class(r[1]), kLabelMoving);
  EXPECT_EQ(instance_id(r[1]), 7u);
  EXPECT_TRUE(is_moving_label(r[1]));
  EXPECT_TRUE(is_moving_label(r[2]));   // SemanticKITTI moving motorcyclist
  EXPECT_FALSE(is_moving_label(r[3]));  // parked car
  EXPECT_FALSE(is_moving_label(r[0]));
}

TEST(LabelFile, CountDifferentFromScanIsAnError) {
  test::TempDir dir;
  write_labels(dir / "000002.label", std::vector<std::uint32_t>(5, kLabelStatic));
  test::expect_error([&] { read_labels(dir / "000002.label", 6); },
                     {"000002.label", "5 labels", "6 points"});
}

}  // namespace
}  // namespace cleanmap

#include "io/score_file.hpp"

namespace cleanmap {
namespace {

TEST(ScoreFile, RoundTripsIncludingNotScoredAndChecksTheCount) {
  test::TempDir dir;
  const std::vector<float> scores{0.0f, 0.25f, std::nanf(""), 1.0f};
  write_scores(dir / "000003.bin", scores);
  const auto r = read_scores(dir / "000003.bin", 4);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_FLOAT_EQ(r[1], 0.25f);
  EXPECT_TRUE(std::isnan(r[2]));
  test::expect_error([&] { read_scores(dir / "000003.bin", 5); }, {"000003.bin", "4 scores", "5 points"});
}

TEST(PerScanFiles, AFullDiskFailsEveryWriteNamingTheFile) {
  // /dev/full refuses every write, as a full disk does. A few hundred bytes stay in the stream's
  // buffer until it is closed: the write must not end before they are out.
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  test::TempDir dir;
  for (const char* name : {"a.label", "a.bin", "kitti.txt", "tum.txt"}) {
    std::filesystem::create_symlink("/dev/full", dir / name);
  }
  test::expect_error(
      [&] { write_labels(dir / "a.label", std::vector<std::uint32_t>(100, kLabelStatic)); },
      {"a.label", "disk full"});
  test::expect_error([&] { write_scores(dir / "a.bin", std::vector<float>(100, 0.5f)); },
                     {"a.bin", "disk full"});
  test::expect_error([&] { write_kitti_poses(dir / "kitti.txt", {Eigen::Isometry3d::Identity()}); },
                     {"kitti.txt", "disk full"});
  test::expect_error([&] { write_tum_poses(dir / "tum.txt", {StampedPose{}}); },
                     {"tum.txt", "disk full"});
}

}  // namespace
}  // namespace cleanmap
