#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "io/raw_cloud.hpp"

namespace cleanmap {

// The ROS 2 messages cleanmap reads from bags, in their CDR form (io/cdr.hpp), decoded without
// ROS: sensor_msgs/msg/PointCloud2, nav_msgs/msg/Odometry, geometry_msgs/msg/TransformStamped
// and tf2_msgs/msg/TFMessage. Encoders write the same layouts (tests build bags with them).

struct PointCloud2Msg {
  double stamp = 0.0;  // header.stamp, seconds
  std::string frame_id;
  std::uint32_t height = 1, width = 0;
  std::vector<RawField> fields;
  bool is_bigendian = false;  // of the point records (not of the CDR around them)
  std::uint32_t point_step = 0, row_step = 0;
  const std::uint8_t* data = nullptr;  // a view into the message's bytes
  std::size_t data_size = 0;
  bool is_dense = true;
};

// A pose at a time: Odometry's pose, a TransformStamped's transform.
struct StampedTransform {
  double stamp = 0.0;
  std::string frame_id, child_frame_id;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// Any message with a std_msgs/Header first: its stamp, in seconds.
double decode_header_stamp(const std::uint8_t* data, std::size_t size, const std::string& what);

PointCloud2Msg decode_point_cloud2(const std::uint8_t* data, std::size_t size, const std::string& what);
StampedTransform decode_odometry(const std::uint8_t* data, std::size_t size, const std::string& what);
StampedTransform decode_transform_stamped(const std::uint8_t* data, std::size_t size, const std::string& what);
std::vector<StampedTransform> decode_tf_message(const std::uint8_t* data, std::size_t size, const std::string& what);

std::vector<std::uint8_t> encode_point_cloud2(const PointCloud2Msg& msg, bool big_endian_cdr = false);
std::vector<std::uint8_t> encode_odometry(const StampedTransform& pose, bool big_endian_cdr = false);
std::vector<std::uint8_t> encode_transform_stamped(const StampedTransform& t, bool big_endian_cdr = false);
std::vector<std::uint8_t> encode_tf_message(const std::vector<StampedTransform>& t, bool big_endian_cdr = false);

// The cloud as scan_from_raw_cloud takes it: padded rows packed and point records swapped to
// little-endian when the message says big-endian, both into `storage` when needed. `source`
// names the message in errors.
RawCloud raw_cloud_of(const PointCloud2Msg& msg, std::vector<std::uint8_t>& storage,
                      const std::string& source = "PointCloud2");

}  // namespace cleanmap
