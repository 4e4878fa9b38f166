#pragma once

// What the ROS 1 and ROS 2 bag readers share: their options, and how a pose topic becomes one
// pose per scan.

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>

namespace cleanmap {

struct BagOptions {
  std::string cloud_topic;   // sensor_msgs PointCloud2; empty: the only PointCloud2 topic
  std::string pose_topic;    // nav_msgs Odometry, geometry_msgs TransformStamped or tf2_msgs TFMessage
  std::string child_frame;   // with tf: the sensor's frame id
};

// A pose from a message; nullopt unless every number is finite and the quaternion has a length
// (a NaN or zero quaternion would turn every later point into NaN).
std::optional<Eigen::Isometry3d> checked_pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

// Pose at time t from a time-sorted track, interpolated between its neighbours; held constant
// beyond the ends. The track must not be empty.
Eigen::Isometry3d pose_at(const std::map<double, Eigen::Isometry3d>& track, double t);

}  // namespace cleanmap
