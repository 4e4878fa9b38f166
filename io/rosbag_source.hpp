#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {

struct BagOptions {
  std::string cloud_topic;   // sensor_msgs/PointCloud2; empty: the only PointCloud2 topic
  std::string pose_topic;    // nav_msgs/Odometry, geometry_msgs/TransformStamped or tf2_msgs/TFMessage
  std::string child_frame;   // with tf: the sensor's frame id
};

// A ROS 1 bag read directly (no ROS installation running): one scan per PointCloud2 message,
// read one at a time; poses from a pose topic interpolated at the scan stamps.
class BagSource {
 public:
  BagSource(const std::filesystem::path& bag, const BagOptions& options);
  ~BagSource();

  std::size_t size() const { return stamps_.size(); }
  const std::vector<double>& stamps() const { return stamps_; }
  const std::vector<Eigen::Isometry3d>& poses() const { return poses_; }  // empty without a pose topic
  std::string topic() const { return topic_; }
  Scan read(std::size_t index, TimeUnit time_unit) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::filesystem::path file_;
  std::string topic_;
  std::vector<double> stamps_;
  std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace cleanmap
