#include "io/kitti_bin.hpp"

#include <fstream>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

Scan three_points() {
  Scan s;
  s.points.resize(3, 3);
  s.points << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  s.intensity.resize(3);
  s.intensity << 0.1f, 0.2f, 0.3f;
  return s;
}

TEST(KittiBin, RoundTripsPointsAndRemission) {
  test::TempDir dir;
  const Scan s = three_points();
  write_kitti_bin(dir / "000007.bin", s);
  const Scan r = read_kitti_bin(dir / "000007.bin");
  EXPECT_EQ(r.name, "000007");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_TRUE(r.points.isApprox(s.points));
  EXPECT_TRUE(r.intensity.isApprox(s.intensity));
  EXPECT_FALSE(r.has_time());
}

TEST(KittiBin, TruncatedFileNamesFileAndSize) {
  test::TempDir dir;
  write_kitti_bin(dir / "a.bin", three_points());
  std::filesystem::resize_file(dir / "a.bin", 3 * 16 - 5);
  test::expect_error([&] { read_kitti_bin(dir / "a.bin"); }, {"a.bin", "43 bytes", "multiple of 16"});
}

TEST(KittiBin, MissingFileIsAnError) {
  test::TempDir dir;
  test::expect_error([&] { read_kitti_bin(dir / "nope.bin"); }, {"nope.bin", "cannot read"});
}

TEST(KittiBin, AnEmptyScanWritesAndReadsBack) {
  // A 0-byte file: Eigen's row views of a 4x0 matrix offset a null pointer (found by fuzz_kitti_bin
  // under UBSan; the sanitizer build of this test fails on the old reader).
  test::TempDir dir;
  Scan empty;
  empty.points.resize(3, 0);
  write_kitti_bin(dir / "000000.bin", empty);
  EXPECT_EQ(std::filesystem::file_size(dir / "000000.bin"), 0u);
  const Scan r = read_kitti_bin(dir / "000000.bin");
  EXPECT_EQ(r.size(), 0u);
  EXPECT_EQ(r.name, "000000");
}

}  // namespace
}  // namespace cleanmap
