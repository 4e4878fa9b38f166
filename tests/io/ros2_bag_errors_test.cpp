// ROS 2 bags: one hand-checked file per storage (bytes asserted where the format fixes them),
// every broken bag one clear error naming it, and `cleanmap run` on both storages end to end.
#include <sqlite3.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "io/label_file.hpp"
#include "io/sequence.hpp"
#include "tests/io/ros2_bag_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;
using test::kFixture;

std::vector<std::uint8_t> file_bytes(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint64_t u64_at(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint64_t v;
  std::memcpy(&v, b.data() + at, 8);
  return v;
}

// One message, uncompressed: the layout below is counted by hand from the MCAP specification.
TEST(Ros2McapFixture, OneMessageFileHasTheSpecifiedBytes) {
  test::TempDir dir;
  {
    McapWriter w(dir / "one.mcap", McapCompression::kNone);
    const auto ch = w.add_channel("/points", "sensor_msgs/msg/PointCloud2");
    w.add_message(ch, 1500000000, kFixture);
    w.close();
  }
  const auto b = file_bytes(dir / "one.mcap");
  const std::uint8_t magic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
  ASSERT_GT(b.size(), 300u);
  EXPECT_EQ(std::memcmp(b.data(), magic, 8), 0);
  EXPECT_EQ(std::memcmp(b.data() + b.size() - 8, magic, 8), 0);
  // Header at 8: opcode 1, length 20 = "ros2" (4 + 4) + "cleanmap" (4 + 8).
  EXPECT_EQ(b[8], 0x01);
  EXPECT_EQ(u64_at(b, 9), 20u);
  EXPECT_EQ(std::string(b.begin() + 21, b.begin() + 25), "ros2");
  // Chunk at 37: records = Schema (9 + 2 + 4+27 + 4+7 + 4 = 57) + Channel (9 + 2 + 2 + 4+7 + 4+3
  // + 4 = 35) + Message (9 + 2 + 4 + 8 + 8 + 73 = 104) = 196 bytes; content = 8 + 8 + 8 + 4 +
  // 4 ("" compression) + 8 + 196 = 236.
  EXPECT_EQ(b[37], 0x06);
  EXPECT_EQ(u64_at(b, 38), 236u);
  EXPECT_EQ(u64_at(b, 46), 1500000000u);  // message_start_time
  EXPECT_EQ(u64_at(b, 62), 196u);         // uncompressed_size
  EXPECT_EQ(b[74], 0u);                   // compression: empty string (length 0)
  EXPECT_EQ(u64_at(b, 78), 196u);         // records length
  EXPECT_EQ(b[86], 0x03);                 // Schema first
  EXPECT_EQ(std::string(b.begin() + 86 + 9 + 2 + 4, b.begin() + 86 + 9 + 2 + 4 + 27), "sensor_msgs/msg/PointCloud2");
  EXPECT_EQ(b[86 + 57], 0x04);            // then Channel
  EXPECT_EQ(b[86 + 57 + 35], 0x05);       // then the Message, its CDR bytes last
  EXPECT_TRUE(std::equal(kFixture.begin(), kFixture.end(), b.begin() + 86 + 196 - 73));
  // A Message Index follows the chunk (at 37 + 9 + 236 = 282); the Footer closes the file.
  EXPECT_EQ(b[282], 0x07);
  EXPECT_EQ(b[b.size() - 8 - 29], 0x02);
  EXPECT_EQ(u64_at(b, b.size() - 8 - 28), 20u);
  // And it reads back: one message, those bytes.
  McapReader r(dir / "one.mcap");
  std::vector<McapMessageRef> refs;
  r.scan({"/points"}, [&](const McapChannel& c, const McapMessageRef& m, const std::uint8_t*, std::size_t) {
    EXPECT_EQ(c.schema_name, "sensor_msgs/msg/PointCloud2");
    refs.push_back(m);
  });
  ASSERT_EQ(refs.size(), 1u);
  EXPECT_EQ(r.read(refs[0]), kFixture);
}

// The sqlite3 file: rosbag2's rows, the message stored as its CDR bytes, and metadata.yaml.
TEST(Ros2SqliteFixture, TheRowsHoldTheHandCheckedMessage) {
  test::TempDir dir;
  {
    SqliteBagWriter w(dir / "b_0.db3");
    w.add_message(w.add_topic("/points", "sensor_msgs/msg/PointCloud2"), 1500000000, kFixture);
  }
  write_ros2_metadata(dir.path, "sqlite3", {"b_0.db3"}, {{"/points", "sensor_msgs/msg/PointCloud2", 1}}, 1500000000, 0);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2((dir / "b_0.db3").c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT t.name, t.type, t.serialization_format, m.timestamp, m.data "
                                   "FROM messages m JOIN topics t ON t.id = m.topic_id", -1, &st, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "/points");
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 1)), "sensor_msgs/msg/PointCloud2");
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 2)), "cdr");
  EXPECT_EQ(sqlite3_column_int64(st, 3), 1500000000);
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, 4));
  ASSERT_EQ(static_cast<std::size_t>(sqlite3_column_bytes(st, 4)), kFixture.size());
  EXPECT_TRUE(std::equal(kFixture.begin(), kFixture.end(), data));
  sqlite3_finalize(st);
  sqlite3_close(db);
  const auto info = read_ros2_metadata(dir.path);
  EXPECT_EQ(info.storage, "sqlite3");
  EXPECT_EQ(info.topics.at("/points"), "sensor_msgs/msg/PointCloud2");
  const auto seq = open_sequence(dir.path);
  ASSERT_EQ(seq.size(), 1u);
  EXPECT_DOUBLE_EQ(seq.times[0], 1.5);
  // x alone is no point: the cloud reader says what is missing, naming the bag, topic and message.
  test::expect_error([&] { load_scan(seq, 0); }, {"/points#0", "has no x, y, z fields"});
}

// A .db3 is data: its `messages` a VIEW over an endless recursive query (issue 45: a 4 KB file
// that hung the run for good) is refused by name, before any query runs it.
TEST(Ros2BagErrors, ASchemaThatDefinesCodeIsNeverRun) {
  test::TempDir dir;
  test::write_ros2_bag(dir / "view", "sqlite3", McapCompression::kNone, 2);
  const fs::path db3 = dir / "view" / "log_0.db3";
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db3.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "DROP TABLE messages; CREATE VIEW messages AS WITH RECURSIVE r(id) AS "
                             "(SELECT 1 UNION ALL SELECT id + 1 FROM r) SELECT id, 1 AS topic_id, "
                             "id AS timestamp, zeroblob(900000000) AS data FROM r;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  test::expect_error([&] { open_sequence(dir / "view"); }, {"log_0.db3", "'messages' is a view", "never run"});
}

// A pose topic that ends before the clouds (issue 45: every later scan silently got the last
// pose) is an error naming the first scan it does not cover.
TEST(Ros2BagErrors, APoseTopicThatEndsBeforeTheCloudsIsRefused) {
  test::TempDir dir;
  test::write_ros2_bag(dir / "short", "sqlite3", McapCompression::kNone, 6);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir / "short" / "log_0.db3").c_str(), &db), SQLITE_OK);
  // Poses at 0.05 s steps from t0: keep those up to 0.25 s (the scans run to 0.5 s; 0.3 s is
  // within half a scan gap of the last pose).
  ASSERT_EQ(sqlite3_exec(db, "DELETE FROM messages WHERE topic_id = (SELECT id FROM topics WHERE name = '/odom') "
                             "AND timestamp > 1700000000270000000;", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  SequenceOptions o;
  o.bag_pose_topic = "/odom";
  test::expect_error([&] { open_sequence(dir / "short", o); }, {"short", "but scan 4 is at", "does not cover the clouds"});
}

TEST(Ros2BagErrors, EachBrokenBagIsOneClearError) {
  test::TempDir dir;
  test::write_ros2_bag(dir / "z", "mcap", McapCompression::kZstd, 3);
  // A topic of another type.
  SequenceOptions odom;
  odom.bag_topic = "/odom";
  test::expect_error([&] { open_sequence(dir / "z", odom); }, {"topic /odom carries nav_msgs/msg/Odometry, not sensor_msgs"});
  // A truncated chunk.
  fs::copy(dir / "z", dir / "cut", fs::copy_options::recursive);
  fs::resize_file(dir / "cut" / "log_0.mcap", fs::file_size(dir / "cut" / "log_0.mcap") / 2);
  test::expect_error([&] { open_sequence(dir / "cut"); }, {"log_0.mcap", "truncated"});
  // An unknown compression ("zstd" renamed in the chunk record).
  fs::copy(dir / "z", dir / "zzzz", fs::copy_options::recursive);
  auto b = file_bytes(dir / "zzzz" / "log_0.mcap");
  const std::string needle = "zstd";
  auto at = std::search(b.begin(), b.end(), needle.begin(), needle.end());
  ASSERT_NE(at, b.end());
  std::copy_n("zzzz", 4, at);
  std::ofstream(dir / "zzzz" / "log_0.mcap", std::ios::binary).write(reinterpret_cast<const char*>(b.data()), b.size());
  test::expect_error([&] { open_sequence(dir / "zzzz"); }, {"log_0.mcap", "unknown compression 'zzzz'"});
  // A channel whose messages are not CDR: named with the file and the channel (issue 45:
  // neither was). The bag's storage file rewritten with /points in another encoding.
  test::write_ros2_bag(dir / "enc", "mcap", McapCompression::kNone, 2);
  {
    McapWriter w(dir / "enc" / "log_0.mcap", McapCompression::kNone);
    const auto ch = w.add_channel("/points", "sensor_msgs/msg/PointCloud2", "json");
    w.add_message(ch, 1700000000000000000, kFixture);
    w.close();
  }
  test::expect_error([&] { open_sequence(dir / "enc"); }, {"log_0.mcap", "(/points) has message encoding 'json'"});
  // A missing metadata.yaml.
  fs::copy(dir / "z", dir / "nometa", fs::copy_options::recursive);
  fs::remove(dir / "nometa" / "metadata.yaml");
  test::expect_error([&] { open_sequence(dir / "nometa"); }, {"nometa", "no metadata.yaml", "ros2 bag reindex"});
  // A storage file that is not sqlite3 at all.
  test::write_ros2_bag(dir / "db", "sqlite3", McapCompression::kNone, 2);
  std::ofstream(dir / "db" / "log_0.db3", std::ios::trunc) << "not a database";
  test::expect_error([&] { open_sequence(dir / "db"); }, {"log_0.db3"});
  // A cloud whose CDR is cut: named with its topic and index when read.
  test::write_ros2_bag(dir / "short", "sqlite3", McapCompression::kNone, 2, [](int i, std::vector<std::uint8_t>& c) {
                                         if (i == 1) c.resize(c.size() / 2);
                                       });
  const auto seq = open_sequence(dir / "short");
  test::expect_error([&] { load_scan(seq, 1); }, {"short", "/points#1", "PointCloud2", "cannot fit"});
  // Through the binary: one line, exit 1, summary incomplete.
  std::string out;
  EXPECT_EQ(test::run_cleanmap("run --input " + (dir / "zzzz").string() + " --out " + (dir / "o").string(), &out), 1);
  EXPECT_NE(out.find("unknown compression 'zzzz'"), std::string::npos) << out;
  EXPECT_FALSE(nlohmann::json::parse(std::ifstream(dir / "o" / "summary.json"))["complete"].get<bool>());
}

TEST(Ros2BagRun, BothStoragesRunEndToEndWithTheSameResult) {
  test::TempDir dir;
  test::write_ros2_bag(dir / "db3", "sqlite3", McapCompression::kNone, 8);
  test::write_ros2_bag(dir / "mcap", "mcap", McapCompression::kLz4, 8);
  for (const char* bag : {"db3", "mcap"}) {
    std::string out;
    ASSERT_EQ(test::run_cleanmap("run --input " + (dir / bag).string() + " --out " + (dir / (std::string(bag) + "-out")).string() +
                                     " --bag-pose-topic /odom --use-given-poses --voxel-size 0.2 --window-half 2",
                                 &out), 0) << out;
    const auto s = nlohmann::json::parse(std::ifstream(dir / (std::string(bag) + "-out") / "summary.json"));
    EXPECT_TRUE(s["complete"].get<bool>());
    EXPECT_EQ(s["layout"].get<std::string>(), "ros2bag");
    EXPECT_EQ(s["scans"].get<int>(), 8);
    EXPECT_GT(s["dynamic_points"].get<int>(), 0);
  }
  for (int i = 0; i < 8; ++i) {  // the same scans and poses give the same decisions
    const std::string name = scan_name(static_cast<std::size_t>(i)) + ".label";
    EXPECT_EQ(read_labels(dir / "db3-out" / "labels" / name), read_labels(dir / "mcap-out" / "labels" / name)) << name;
  }
}

}  // namespace
}  // namespace cleanmap
