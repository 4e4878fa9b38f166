// ROS 1 bags written with the same library (Debian's rosbag_storage), read back as sequences.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "io/sequence.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "tests/io/bag_test_support.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// x y z intensity (float32) and t (uint32, nanoseconds after the header stamp), as an Ouster
// driver publishes them.
sensor_msgs::PointCloud2 to_message(const Scan& scan, double stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp = ros::Time(stamp);
  msg.header.frame_id = "os_sensor";
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(scan.size());
  const char* names[] = {"x", "y", "z", "intensity", "t"};
  for (std::uint32_t k = 0; k < 5; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = k < 4 ? sensor_msgs::PointField::FLOAT32 : sensor_msgs::PointField::UINT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  msg.point_step = 20;
  msg.row_step = msg.point_step * msg.width;
  msg.data = test::ouster_records(scan);
  return msg;
}

// Changes a message before it is written (message index i: odometry every 0.05 s, a cloud on even i).
using Tamper = std::function<void(int i, nav_msgs::Odometry&, sensor_msgs::PointCloud2*)>;

// Six scans of the synthetic street at 10 Hz and its poses as Odometry at 20 Hz.
std::vector<SyntheticScan> write_bag(const std::filesystem::path& file, int scans = 6, const Tamper& tamper = {}) {
  LidarModel lidar;
  lidar.beams = 32;
  lidar.columns = 512;
  const auto world = make_street_world(5);
  std::vector<SyntheticScan> out;
  rosbag::Bag bag;
  bag.open(file.string(), rosbag::bagmode::Write);
  const double t0 = 1700000000.0;
  for (int i = 0; i < 2 * scans; ++i) {
    const double t = 0.05 * i;
    const auto pose = sensor_pose(world, t);
    nav_msgs::Odometry odom;
    odom.header.stamp = ros::Time(t0 + t);
    const Eigen::Quaterniond q(pose.rotation());
    odom.pose.pose.position.x = pose.translation().x();
    odom.pose.pose.position.y = pose.translation().y();
    odom.pose.pose.position.z = pose.translation().z();
    odom.pose.pose.orientation.w = q.w();
    odom.pose.pose.orientation.x = q.x();
    odom.pose.pose.orientation.y = q.y();
    odom.pose.pose.orientation.z = q.z();
    sensor_msgs::PointCloud2 cloud;
    if (i % 2 == 0) {
      out.push_back(simulate_scan(world, lidar, static_cast<std::size_t>(i / 2), 5));
      cloud = to_message(out.back().scan, t0 + t);
    }
    if (tamper) tamper(i, odom, i % 2 == 0 ? &cloud : nullptr);
    bag.write("/odom", odom.header.stamp, odom);
    if (i % 2 == 0) bag.write("/os_cloud_node/points", ros::Time(t0 + t), cloud);
  }
  bag.close();
  return out;
}

TEST(RosBag, PointCloudsTimesAndOdometryPosesReadBack) {
  test::TempDir dir;
  const auto truth = write_bag(dir / "log.bag");
  SequenceOptions o;
  o.bag_pose_topic = "/odom";
  const auto seq = open_sequence(dir / "log.bag", o);
  EXPECT_EQ(seq.layout, "rosbag");
  test::expect_same_scans(seq, truth);
}

TEST(RosBag, TruncatedBagAndUnknownTopicAreClearErrors) {
  test::TempDir dir;
  write_bag(dir / "log.bag");
  SequenceOptions o;
  o.bag_topic = "/nope";
  test::expect_error([&] { open_sequence(dir / "log.bag", o); }, {"log.bag", "/nope"});
  std::filesystem::copy_file(dir / "log.bag", dir / "cut.bag");
  std::filesystem::resize_file(dir / "cut.bag", std::filesystem::file_size(dir / "cut.bag") / 3);
  test::expect_error([&] { open_sequence(dir / "cut.bag"); }, {"cut.bag"});
}

TEST(RosBag, LyingPointLayoutsAndNanPosesAreClearErrors) {
  test::TempDir dir;
  // Scan 1: a field's offset beyond point_step (read past the buffer before); scan 2: point_step 0.
  write_bag(dir / "layout.bag", 3, [](int i, nav_msgs::Odometry&, sensor_msgs::PointCloud2* c) {
    if (c && i == 2) c->fields[2].offset = 40;
    if (c && i == 4) c->point_step = 0;
  });
  const auto seq = open_sequence(dir / "layout.bag");
  EXPECT_EQ(load_scan(seq, 0).scan.size(), load_scan(seq, 0).scan.input_size);
  test::expect_error([&] { load_scan(seq, 1); }, {"layout.bag", "#1", "field 'z'", "beyond the point step"});
  test::expect_error([&] { load_scan(seq, 2); }, {"layout.bag", "#2", "beyond the point step of 0 bytes"});
  write_bag(dir / "nan.bag", 3, [](int i, nav_msgs::Odometry& o, sensor_msgs::PointCloud2*) {
    if (i == 3) o.pose.pose.orientation.w = std::nan("");
  });
  SequenceOptions o;
  o.bag_pose_topic = "/odom";
  test::expect_error([&] { open_sequence(dir / "nan.bag", o); }, {"nan.bag", "/odom", "message 3", "not a finite pose"});
  std::string out;
  EXPECT_EQ(test::run_cleanmap("run --input " + (dir / "layout.bag").string() + " --out " + (dir / "out").string(), &out), 1)
      << out;
  EXPECT_NE(out.find("beyond the point step"), std::string::npos) << out;
}

TEST(RosBag, RunTakesABagEndToEnd) {
  test::TempDir dir;
  write_bag(dir / "log.bag", 8);
  std::string out;
  ASSERT_EQ(test::run_cleanmap("run --input " + (dir / "log.bag").string() + " --out " + (dir / "out").string() +
                                   " --bag-pose-topic /odom --use-given-poses --voxel-size 0.2 --window-half 2",
                               &out), 0) << out;
  const auto s = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  EXPECT_TRUE(s["complete"].get<bool>());
  EXPECT_EQ(s["layout"].get<std::string>(), "rosbag");
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "labels" / "000007.label"));
}

}  // namespace
}  // namespace cleanmap
