#pragma once

// What the ROS 1 and ROS 2 bag readers share: their options, and how a pose topic becomes one
// pose per scan.

#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cleanmap {

struct BagOptions {
  std::string cloud_topic;   // sensor_msgs PointCloud2; empty: the only PointCloud2 topic
  std::string pose_topic;    // nav_msgs Odometry, geometry_msgs TransformStamped or tf2_msgs TFMessage
  std::string child_frame;   // with tf: the sensor's frame id
};

// A pose from a message; nullopt unless every number is finite and the quaternion has a length
// (a NaN or zero quaternion would turn every later point into NaN).
std::optional<Eigen::Isometry3d> checked_pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

// A pose track covers the scans when each scan's stamp lies inside it or within half a scan
// gap of an end (mocap or odometry starting a few ms late); beyond that a held pose would be
// wrong (issue 45: a pose topic that ended before the clouds gave every later scan the last
// pose, silently). Throws Error naming `source`, the first scan outside, and `advice`.
void check_coverage(const std::filesystem::path& source, const std::map<double, Eigen::Isometry3d>& track,
                    const std::vector<double>& times, const std::string& what, const std::string& advice);

// Pose at time t from a time-sorted track, interpolated between its neighbours; held constant
// beyond the ends. The track must not be empty.
Eigen::Isometry3d pose_at(const std::map<double, Eigen::Isometry3d>& track, double t);

}  // namespace cleanmap
