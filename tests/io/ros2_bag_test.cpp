// ROS 2 bags (sqlite3 and mcap storage, CDR messages) written here with the same code the
// reader shares (io/cdr, io/mcap_records, io/sqlite_bag), read back as sequences; one
// hand-checked fixture per storage; every way a bag can be broken gives one clear error.
#include <algorithm>
#include <cstring>

#include "io/sequence.hpp"
#include "tests/io/ros2_bag_support.hpp"

namespace cleanmap {
namespace {
using test::kFixture;
using test::fixture_message;
using test::write_ros2_bag;

TEST(Ros2Cdr, APointCloud2MatchesItsHandCheckedBytesAndReadsBack) {
  EXPECT_EQ(encode_point_cloud2(fixture_message()), kFixture);
  const auto m = decode_point_cloud2(kFixture.data(), kFixture.size(), "fixture");
  EXPECT_DOUBLE_EQ(m.stamp, 1.5);
  EXPECT_EQ(m.frame_id, "l");
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "x");
  float x;
  std::memcpy(&x, m.data, 4);
  EXPECT_EQ(x, 1.0f);
  // Big-endian CDR: the same message, every number reversed, reads back the same.
  const auto be = encode_point_cloud2(fixture_message(), true);
  EXPECT_EQ(be[1], 0x00);
  EXPECT_EQ(be[4 + 3], 0x01);  // sec 1, most significant byte first
  const auto back = decode_point_cloud2(be.data(), be.size(), "big-endian");
  EXPECT_DOUBLE_EQ(back.stamp, 1.5);
  EXPECT_EQ(back.point_step, 4u);
  // Cut anywhere, it is an error naming the message, never a read past its end.
  for (std::size_t n : {std::size_t{3}, std::size_t{10}, std::size_t{40}, kFixture.size() - 1}) {
    test::expect_error([&] { decode_point_cloud2(kFixture.data(), n, "cut"); }, {"cut", "PointCloud2"});
  }
}

// An organised cloud whose rows are padded (row_step > width * point_step, legal in ROS; issue
// 45: every row after the first was read shifted by the padding), big-endian or not.
TEST(Ros2Cdr, PaddedRowsAreReadRowByRow) {
  for (const bool big : {false, true}) {
    // 2 rows of 3 points (x y z float32), each row padded by 4 bytes.
    std::vector<std::uint8_t> data(2 * (3 * 12 + 4), 0xEE);
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
          const float v = static_cast<float>(100 * r + 10 * c + k);
          std::uint8_t b[4];
          std::memcpy(b, &v, 4);
          if (big) std::reverse(b, b + 4);
          std::memcpy(data.data() + r * 40 + c * 12 + k * 4, b, 4);
        }
      }
    }
    PointCloud2Msg m;
    m.width = 3;
    m.height = 2;
    m.fields = {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}};
    m.is_bigendian = big;
    m.point_step = 12;
    m.row_step = 40;
    m.data = data.data();
    m.data_size = data.size();
    std::vector<std::uint8_t> storage;
    const Scan s = scan_from_raw_cloud(raw_cloud_of(m, storage, "padded"), "padded", TimeUnit::kAuto);
    ASSERT_EQ(s.size(), 6u);
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(s.points(k, 3 * r + c), static_cast<float>(100 * r + 10 * c + k)) << big;
      }
    }
    m.row_step = 30;  // shorter than a row's points
    test::expect_error([&] { raw_cloud_of(m, storage, "short"); }, {"short", "row_step 30 is shorter than a row's 3 points"});
    m.row_step = 400;  // rows the data cannot hold
    test::expect_error([&] { raw_cloud_of(m, storage, "long"); }, {"long", "fewer than 2 rows of row_step 400"});
  }
}

// Rows of no points but a padded row_step (found by fuzz_ros2_cdr in CI): nothing to pack, and
// the empty storage's null pointer must not reach memcpy (UBSan flags it in the sanitizer suite).
TEST(Ros2Cdr, PaddedRowsOfNoPointsAreAnEmptyScan) {
  std::vector<std::uint8_t> data(8, 0);
  PointCloud2Msg m;
  m.width = 0;
  m.height = 2;
  m.fields = {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}};
  m.point_step = 12;
  m.row_step = 4;
  m.data = data.data();
  m.data_size = data.size();
  std::vector<std::uint8_t> storage;
  const Scan s = scan_from_raw_cloud(raw_cloud_of(m, storage, "empty rows"), "empty rows", TimeUnit::kAuto);
  EXPECT_EQ(s.size(), 0u);
  m.point_step = 0;  // a point step of 0 with points claimed is refused, not divided by
  m.width = 3;
  test::expect_error([&] { scan_from_raw_cloud(raw_cloud_of(m, storage, "step 0"), "step 0", TimeUnit::kAuto); },
                     {"step 0"});
}

TEST(Ros2Cdr, BigEndianPointRecordsAreSwappedAndPosesRoundTrip) {
  const float v[3] = {1.5f, -2.0f, 3.25f};
  std::uint8_t be[12];
  for (int k = 0; k < 3; ++k) {
    std::uint8_t b[4];
    std::memcpy(b, &v[k], 4);
    for (int j = 0; j < 4; ++j) be[4 * k + j] = b[3 - j];
  }
  PointCloud2Msg m;
  m.width = 1;
  m.fields = {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}};
  m.is_bigendian = true;
  m.point_step = m.row_step = 12;
  m.data = be;
  m.data_size = 12;
  std::vector<std::uint8_t> storage;
  const Scan s = scan_from_raw_cloud(raw_cloud_of(m, storage), "be", TimeUnit::kAuto);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s.points(0, 0), 1.5f);
  EXPECT_EQ(s.points(1, 0), -2.0f);
  EXPECT_EQ(s.points(2, 0), 3.25f);
  // Fuzzing finding: an offset near 2^32 wrapped the "inside the point step" check of the swap.
  m.fields.push_back({"intensity", 0xFFFFFFFEu, 7});
  test::expect_error([&] { scan_from_raw_cloud(raw_cloud_of(m, storage), "be", TimeUnit::kAuto); },
                     {"be", "field 'intensity'", "beyond the point step"});
  StampedTransform t;
  t.stamp = 12.25;
  t.child_frame_id = "lidar";
  t.translation = {1, 2, 3};
  t.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  for (bool big : {false, true}) {
    const auto o = encode_odometry(t, big);
    const auto r = decode_odometry(o.data(), o.size(), "odom");
    EXPECT_DOUBLE_EQ(r.stamp, 12.25);
    EXPECT_EQ(r.child_frame_id, "lidar");
    EXPECT_TRUE(r.translation.isApprox(t.translation));
    EXPECT_TRUE(r.rotation.isApprox(t.rotation));
    const auto tf = encode_tf_message({t, t}, big);
    EXPECT_EQ(decode_tf_message(tf.data(), tf.size(), "tf").size(), 2u);
  }
}

struct StorageCase {
  const char* name;
  const char* storage;
  McapCompression compression;
};

void PrintTo(const StorageCase& c, std::ostream* os) { *os << c.name; }

class Ros2Storage : public testing::TestWithParam<StorageCase> {};

TEST_P(Ros2Storage, CloudsTimesAndOdometryPosesReadBack) {
  test::TempDir dir;
  const auto truth = write_ros2_bag(dir / "bag", GetParam().storage, GetParam().compression);
  SequenceOptions o;
  o.bag_pose_topic = "/odom";
  const auto seq = open_sequence(dir / "bag", o);
  EXPECT_EQ(seq.layout, "ros2bag");
  test::expect_same_scans(seq, truth);
}

INSTANTIATE_TEST_SUITE_P(AllStorages, Ros2Storage,
                         testing::Values(StorageCase{"sqlite3", "sqlite3", McapCompression::kNone},
                                         StorageCase{"mcap", "mcap", McapCompression::kNone},
                                         StorageCase{"mcap_zstd", "mcap", McapCompression::kZstd},
                                         StorageCase{"mcap_lz4", "mcap", McapCompression::kLz4}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace cleanmap
