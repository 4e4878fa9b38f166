#include "io/sequence.hpp"

#include <fstream>

#include "io/cloud_file.hpp"
#include "io/kitti_bin.hpp"
#include "io/label_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

Scan cube(int n, float offset) {
  Scan s;
  s.points = Eigen::Matrix3Xf::Random(3, n).array() + offset;
  s.intensity = Eigen::VectorXf::Ones(n);
  return s;
}

TEST(Sequence, MissingAndEmptyFoldersAreErrors) {
  test::TempDir dir;
  test::expect_error([&] { open_sequence(dir / "absent"); }, {"absent", "no such folder"});
  test::expect_error([&] { open_sequence(dir.path); }, {dir.path.string(), "no scan files"});
}

// Two scan files of one name would write one set of outputs (issue 45: two depth frames named
// alike in two folders overwrote each other's labels).
TEST(Sequence, ScansSharingANameAreRefused) {
  test::TempDir dir;
  write_kitti_bin(dir / "a.bin", cube(4, 0));
  write_cloud(dir / "a.pcd", cube(4, 1));
  test::expect_error([&] { open_sequence(dir.path); }, {"scans a.bin and a.pcd share the name 'a'", "rename one"});
}

TEST(Sequence, PlainFolderSortedByNameSpacedByRate) {
  test::TempDir dir;
  write_kitti_bin(dir / "b.bin", cube(5, 1));
  write_kitti_bin(dir / "a.bin", cube(4, 0));
  SequenceOptions o;
  o.rate_hz = 20;
  const auto seq = open_sequence(dir.path, o);
  EXPECT_EQ(seq.layout, "plain-folder");
  ASSERT_EQ(seq.size(), 2u);
  EXPECT_EQ(seq.scans[0].filename(), "a.bin");
  EXPECT_DOUBLE_EQ(seq.times[1], 0.05);
  EXPECT_FALSE(seq.has_poses());
  const auto s = load_scan(seq, 1);
  EXPECT_EQ(s.scan.name, "b");
  EXPECT_EQ(s.scan.size(), 5u);
  EXPECT_DOUBLE_EQ(s.scan.stamp, 0.05);
}

TEST(Sequence, KittiLayoutWithPosesTimesAndLabels) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "velodyne");
  std::filesystem::create_directories(dir / "labels");
  for (int i = 0; i < 3; ++i) {
    write_kitti_bin(dir / "velodyne" / ("00000" + std::to_string(i) + ".bin"), cube(6, i));
  }
  write_labels(dir / "labels" / "000001.label", std::vector<std::uint32_t>(6, kLabelMoving));
  std::ofstream(dir / "times.txt") << "0\n0.1\n0.2\n";
  std::ofstream(dir / "poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n"
                                      "1 0 0 2 0 1 0 0 0 0 1 0\n";
  const auto seq = open_sequence(dir.path);
  EXPECT_EQ(seq.layout, "kitti");
  EXPECT_TRUE(seq.has_poses());
  EXPECT_TRUE(seq.has_labels());
  EXPECT_TRUE(seq.labels[0].empty());
  const auto s = load_scan(seq, 1);
  EXPECT_EQ(s.labels.size(), 6u);
  EXPECT_NEAR(s.scan.pose->translation().x(), 1.0, 1e-12);
}

TEST(Sequence, PoseAndTimeCountsMustMatchScans) {
  test::TempDir dir;
  write_kitti_bin(dir / "000000.bin", cube(3, 0));
  write_kitti_bin(dir / "000001.bin", cube(3, 0));
  std::ofstream(dir / "poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  test::expect_error([&] { open_sequence(dir.path); }, {"poses.txt", "1 poses", "2 scans"});
  std::filesystem::remove(dir / "poses.txt");
  std::ofstream(dir / "times.txt") << "0\n0.1\n0.2\n";
  test::expect_error([&] { open_sequence(dir.path); }, {"times.txt", "3 times", "2 scans"});
  std::ofstream(dir / "times.txt") << "0\n0\n";
  test::expect_error([&] { open_sequence(dir.path); }, {"times.txt", "increase"});
}

TEST(Sequence, LabelCountMismatchNamesTheLabelFile) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "scans");
  std::filesystem::create_directories(dir / "labels");
  write_kitti_bin(dir / "scans" / "000000.bin", cube(4, 0));
  write_labels(dir / "labels" / "000000.label", std::vector<std::uint32_t>(3, kLabelStatic));
  const auto seq = open_sequence(dir.path);
  test::expect_error([&] { load_scan(seq, 0); }, {"000000.label", "3 labels", "4 points"});
}

TEST(Sequence, NanPointsDroppedAndLabelsKeptAligned) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "scans");
  std::filesystem::create_directories(dir / "labels");
  Scan s = cube(4, 0);
  s.points(1, 1) = std::nanf("");
  write_kitti_bin(dir / "scans" / "000000.bin", s);
  write_labels(dir / "labels" / "000000.label", {1, 2, 3, 4});
  const auto loaded = load_scan(open_sequence(dir.path), 0);
  EXPECT_EQ(loaded.dropped_non_finite, 1u);
  EXPECT_EQ(loaded.labels, (std::vector<std::uint32_t>{1, 3, 4}));
  EXPECT_EQ(loaded.scan.input_size, 4u);
}

}  // namespace
}  // namespace cleanmap
