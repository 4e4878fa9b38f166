#pragma once

// Builds ROS 2 bags for tests with the writers that share their layouts with the reader.

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>

#include "io/mcap_file.hpp"
#include "io/ros2_bag.hpp"
#include "io/ros2_messages.hpp"
#include "io/sqlite_bag.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "tests/io/bag_test_support.hpp"
#include "tests/test_support.hpp"

namespace cleanmap::test {
namespace fs = std::filesystem;

// PointCloud2 of one point (1, 0, 0 as float32 x only), stamp 1.5 s, frame "l", byte by byte
// as CDR lays it out (offsets after the 4-byte encapsulation header).
inline const std::vector<std::uint8_t> kFixture = {
    0x00, 0x01, 0x00, 0x00,  // CDR little-endian
    0x01, 0x00, 0x00, 0x00,  // 0: stamp.sec 1
    0x00, 0x65, 0xCD, 0x1D,  // 4: stamp.nanosec 500000000
    0x02, 0x00, 0x00, 0x00, 'l', 0x00,  // 8: frame_id "l" (length counts the NUL)
    0x00, 0x00,              // 14: padding to 4
    0x01, 0x00, 0x00, 0x00,  // 16: height 1
    0x01, 0x00, 0x00, 0x00,  // 20: width 1
    0x01, 0x00, 0x00, 0x00,  // 24: one field
    0x02, 0x00, 0x00, 0x00, 'x', 0x00, 0x00, 0x00,  // 28: name "x", padding
    0x00, 0x00, 0x00, 0x00,  // 36: offset 0
    0x07, 0x00, 0x00, 0x00,  // 40: datatype FLOAT32, padding
    0x01, 0x00, 0x00, 0x00,  // 44: count 1
    0x00, 0x00, 0x00, 0x00,  // 48: is_bigendian false, padding
    0x04, 0x00, 0x00, 0x00,  // 52: point_step 4
    0x04, 0x00, 0x00, 0x00,  // 56: row_step 4
    0x04, 0x00, 0x00, 0x00,  // 60: data: 4 bytes
    0x00, 0x00, 0x80, 0x3F,  // 64: 1.0f
    0x01,                    // 68: is_dense
};

inline PointCloud2Msg fixture_message() {
  static const float one = 1.0f;
  PointCloud2Msg m;
  m.stamp = 1.5;
  m.frame_id = "l";
  m.width = 1;
  m.fields = {{"x", 0, 7}};
  m.point_step = m.row_step = 4;
  m.data = reinterpret_cast<const std::uint8_t*>(&one);
  m.data_size = 4;
  return m;
}

// A PointCloud2 of the scan's Ouster-style records.
inline std::vector<std::uint8_t> cloud_bytes(const Scan& scan, double stamp) {
  const auto data = ouster_records(scan);
  PointCloud2Msg m;
  m.stamp = stamp;
  m.frame_id = "os_sensor";
  m.width = static_cast<std::uint32_t>(scan.size());
  m.fields = {{"x", 0, 7}, {"y", 4, 7}, {"z", 8, 7}, {"intensity", 12, 7}, {"t", 16, 6}};
  m.point_step = 20;
  m.row_step = 20 * m.width;
  m.data = data.data();
  m.data_size = data.size();
  return encode_point_cloud2(m);
}

using Tamper = std::function<void(int scan, std::vector<std::uint8_t>& cdr)>;  // changes a cloud's bytes

// The synthetic street at 10 Hz on /points and its poses as Odometry at 20 Hz on /odom.
inline std::vector<SyntheticScan> write_ros2_bag(const fs::path& folder, const std::string& storage,
                                                 McapCompression compression = McapCompression::kNone, int scans = 6,
                                                 const Tamper& tamper = {}) {
  struct {
    const std::string& storage;
    McapCompression compression;
    int scans;
    const Tamper& tamper;
  } spec{storage, compression, scans, tamper};
  fs::create_directories(folder);
  LidarModel lidar;
  lidar.beams = 32;
  lidar.columns = 512;
  const auto world = make_street_world(5);
  std::vector<SyntheticScan> out;
  const double t0 = 1700000000.0;
  const std::string file = spec.storage == "sqlite3" ? "log_0.db3" : "log_0.mcap";
  std::unique_ptr<SqliteBagWriter> db;
  std::unique_ptr<McapWriter> mcap;
  std::int64_t points = 0, odom = 0;
  if (spec.storage == "sqlite3") {
    db = std::make_unique<SqliteBagWriter>(folder / file);
    points = db->add_topic("/points", "sensor_msgs/msg/PointCloud2");
    odom = db->add_topic("/odom", "nav_msgs/msg/Odometry");
  } else {
    mcap = std::make_unique<McapWriter>(folder / file, spec.compression, 256 * 1024);
    points = mcap->add_channel("/points", "sensor_msgs/msg/PointCloud2");
    odom = mcap->add_channel("/odom", "nav_msgs/msg/Odometry");
  }
  auto add = [&](std::int64_t topic, double t, const std::vector<std::uint8_t>& bytes) {
    const auto ns = static_cast<std::int64_t>(std::llround(t * 1e9));
    if (db) db->add_message(topic, ns, bytes);
    else mcap->add_message(static_cast<std::uint16_t>(topic), static_cast<std::uint64_t>(ns), bytes);
  };
  for (int i = 0; i < 2 * spec.scans; ++i) {
    const double t = 0.05 * i;
    const auto pose = sensor_pose(world, t);
    StampedTransform o;
    o.stamp = t0 + t;
    o.frame_id = "odom";
    o.child_frame_id = "os_sensor";
    o.translation = pose.translation();
    o.rotation = Eigen::Quaterniond(pose.rotation());
    add(odom, t0 + t, encode_odometry(o));
    if (i % 2 == 0) {
      out.push_back(simulate_scan(world, lidar, static_cast<std::size_t>(i / 2), 5));
      auto bytes = cloud_bytes(out.back().scan, t0 + t);
      if (spec.tamper) spec.tamper(i / 2, bytes);
      add(points, t0 + t, bytes);
    }
  }
  if (mcap) mcap->close();
  write_ros2_metadata(folder, spec.storage, {file},
                      {{"/points", "sensor_msgs/msg/PointCloud2", static_cast<std::size_t>(spec.scans)},
                       {"/odom", "nav_msgs/msg/Odometry", static_cast<std::size_t>(2 * spec.scans)}},
                      static_cast<std::int64_t>(t0 * 1e9), static_cast<std::int64_t>(0.1e9 * spec.scans));
  return out;
}

}  // namespace cleanmap::test
