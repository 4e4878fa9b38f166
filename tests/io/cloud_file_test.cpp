#include "io/cloud_file.hpp"

#include <fstream>

#include "io/error.hpp"
#include "io/sequence.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

Scan timed_scan() {
  Scan s;
  s.points = Eigen::Matrix3Xf::Random(3, 50) * 20;
  s.intensity = Eigen::VectorXf::LinSpaced(50, 0, 49);
  s.time = Eigen::VectorXf::LinSpaced(50, 0.0f, 0.099f);
  return s;
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

TEST(CloudFile, BinaryPcdRoundTripsAllFields) {
  test::TempDir dir;
  const Scan s = timed_scan();
  std::vector<float> score(50, 0.25f);
  write_cloud(dir / "a.pcd", s, {{"score", score}});
  const Scan r = read_cloud(dir / "a.pcd");
  EXPECT_TRUE(r.points.isApprox(s.points));
  EXPECT_TRUE(r.intensity.isApprox(s.intensity));
  ASSERT_TRUE(r.has_time());
  EXPECT_TRUE(r.time.isApprox(s.time));
  EXPECT_FALSE(r.pose.has_value());
}

TEST(CloudFile, CompressedPcdAndPlyRoundTrip) {
  test::TempDir dir;
  const Scan s = timed_scan();
  CloudWriteOptions compressed;
  compressed.compressed = true;
  write_cloud(dir / "c.pcd", s, {}, compressed);
  write_cloud(dir / "p.ply", s);
  for (const char* name : {"c.pcd", "p.ply"}) {
    const Scan r = read_cloud(dir / name);
    EXPECT_TRUE(r.points.isApprox(s.points)) << name;
    EXPECT_TRUE(r.intensity.isApprox(s.intensity)) << name;
    EXPECT_TRUE(r.time.isApprox(s.time)) << name;
  }
}

TEST(CloudFile, AFullDiskFailsTheWriteNamingTheFile) {
  // /dev/full refuses every write (ENOSPC), as a full disk does. PCL's PCD file writer maps the
  // file into memory, and on a full disk the copy into it killed the process with SIGBUS.
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  test::TempDir dir;
  Scan big = timed_scan();
  big.points = Eigen::Matrix3Xf::Random(3, 100000);  // more than a stream's buffer
  big.intensity = Eigen::VectorXf::Zero(100000);
  big.time = Eigen::VectorXf::Zero(100000);
  CloudWriteOptions compressed;
  compressed.compressed = true;
  for (const char* name : {"a.pcd", "c.pcd", "p.ply"}) {
    std::filesystem::create_symlink("/dev/full", dir / name);
    const auto options = std::string(name) == "c.pcd" ? compressed : CloudWriteOptions{};
    test::expect_error([&] { write_cloud(dir / name, big, {}, options); }, {name, "disk full"});
  }
}

TEST(CloudFile, ViewpointBecomesPose) {
  test::TempDir dir;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(1, 2, 3)).rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  CloudWriteOptions o;
  o.viewpoint = pose;
  write_cloud(dir / "v.pcd", timed_scan(), {}, o);
  const Scan r = read_cloud(dir / "v.pcd");
  ASSERT_TRUE(r.pose.has_value());
  EXPECT_TRUE(r.pose->isApprox(pose, 1e-5));
}

TEST(CloudFile, AsciiPcdWithDoubleXyzAndNanosecondTimes) {
  test::TempDir dir;
  write_text(dir / "a.pcd",
             "VERSION 0.7\nFIELDS x y z intensity timestamp\nSIZE 8 8 8 2 4\nTYPE F F F U U\n"
             "COUNT 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
             "1 2 3 10 0\n4 5 6 20 50000000\n7 8 9 30 99000000\n");
  const Scan r = read_cloud(dir / "a.pcd");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_FLOAT_EQ(r.points(2, 2), 9.0f);
  EXPECT_FLOAT_EQ(r.intensity[1], 20.0f);
  ASSERT_TRUE(r.has_time());
  EXPECT_NEAR(r.time[1], 0.05, 1e-7);  // nanoseconds detected from the spread
  EXPECT_NEAR(r.time[2], 0.099, 1e-7);
  CloudReadOptions us;
  us.time_unit = TimeUnit::kMicroseconds;
  EXPECT_NEAR(read_cloud(dir / "a.pcd", us).time[1], 50.0, 1e-4);  // explicit unit wins
}

TEST(CloudFile, EpochTimesBecomeStampPlusOffsets) {
  test::TempDir dir;
  write_text(dir / "e.pcd",
             "VERSION 0.7\nFIELDS x y z time\nSIZE 4 4 4 8\nTYPE F F F F\nCOUNT 1 1 1 1\n"
             "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
             "1 2 3 1630577758.50\n4 5 6 1630577758.55\n");
  const Scan r = read_cloud(dir / "e.pcd");
  EXPECT_NEAR(r.stamp, 1630577758.50, 1e-6);
  EXPECT_NEAR(r.time[1], 0.05, 1e-6);
}

TEST(CloudFile, NanAndAbsurdPointsAreDroppedWithACount) {
  test::TempDir dir;
  // A return 1e12 m away and one fired 1e20 s from its scan (issue 45: both crashed the run).
  write_text(dir / "n.pcd",
             "VERSION 0.7\nFIELDS x y z t\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
             "WIDTH 6\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 6\nDATA ascii\n"
             "1 2 3 0\nnan nan nan 0\n4 5 6 0.05\ninf 0 0 0\n1e12 0 0 0.01\n7 8 9 1e20\n");
  Scan r = read_cloud(dir / "n.pcd", {TimeUnit::kSeconds});
  const DroppedPoints d = drop_invalid(r);
  EXPECT_EQ(d.non_finite, 2u);
  EXPECT_EQ(d.out_of_range, 2u);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_FLOAT_EQ(r.points(0, 1), 4.0f);
  // Per-point outputs still come back in input order, with a fill for the dropped points.
  const auto scattered = to_input_order(r, std::vector<int>{7, 8}, -1);
  EXPECT_EQ(scattered, (std::vector<int>{7, -1, 8, -1, -1, -1}));
}

TEST(CloudFile, MissingXyzIsAnError) {
  test::TempDir dir;
  write_text(dir / "m.pcd",
             "VERSION 0.7\nFIELDS a b\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\n"
             "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n");
  test::expect_error([&] { read_cloud(dir / "m.pcd"); }, {"m.pcd", "no x, y, z"});
}

TEST(CloudFile, UnknownFieldTypeIsAnError) {
  test::TempDir dir;
  write_text(dir / "u.pcd",
             "VERSION 0.7\nFIELDS x y z w\nSIZE 4 4 4 4\nTYPE F F F Q\nCOUNT 1 1 1 1\nWIDTH 1\n"
             "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3 4\n");
  test::expect_error([&] { read_cloud(dir / "u.pcd"); }, {"u.pcd"});
}

TEST(CloudFile, TruncatedBinaryPcdIsAnError) {
  test::TempDir dir;
  // PCL pads binary files; cut into the data itself.
  write_cloud(dir / "t.pcd", timed_scan());
  std::filesystem::resize_file(dir / "t.pcd", 600);
  test::expect_error([&] { read_cloud(dir / "t.pcd"); }, {"t.pcd", "truncated"});
  CloudWriteOptions compressed;
  compressed.compressed = true;
  write_cloud(dir / "tc.pcd", timed_scan(), {}, compressed);
  std::filesystem::resize_file(dir / "tc.pcd", 600);
  test::expect_error([&] { read_cloud(dir / "tc.pcd"); }, {"tc.pcd"});
}

TEST(CloudFile, UnsupportedExtensionIsAnError) {
  test::TempDir dir;
  write_text(dir / "x.xyz", "1 2 3\n");
  test::expect_error([&] { read_cloud(dir / "x.xyz"); }, {"x.xyz", "unsupported"});
}

}  // namespace
}  // namespace cleanmap
