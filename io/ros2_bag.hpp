#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/bag_common.hpp"
#include "io/cloud_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {

// A ROS 2 bag read directly, without ROS: the bag folder's metadata.yaml names the storage
// (sqlite3 .db3 files or mcap files) and its topics with their types; messages are CDR
// (io/ros2_messages.hpp). One scan per sensor_msgs/msg/PointCloud2 message, read one at a time
// in stamp order; poses from a pose topic (nav_msgs/msg/Odometry,
// geometry_msgs/msg/TransformStamped, tf2_msgs/msg/TFMessage with child_frame) interpolated at
// the scan stamps, as for ROS 1 bags. rosbag2's per-message zstd compression is read; its
// whole-file compression is not (an Error says how to undo it).
struct Ros2BagInfo {
  std::string storage;                        // "sqlite3" or "mcap"
  std::vector<std::filesystem::path> files;   // relative_file_paths, resolved
  std::map<std::string, std::string> topics;  // name -> type
  std::string compression_format, compression_mode;
};

bool is_ros2_bag(const std::filesystem::path& folder);  // a folder with metadata.yaml
Ros2BagInfo read_ros2_metadata(const std::filesystem::path& folder);

// metadata.yaml for a bag folder written by tests: storage, files, topics (name, type, count).
struct Ros2TopicCount {
  std::string name, type;
  std::size_t count = 0;
};
void write_ros2_metadata(const std::filesystem::path& folder, const std::string& storage,
                         const std::vector<std::string>& files, const std::vector<Ros2TopicCount>& topics,
                         std::int64_t start_ns, std::int64_t duration_ns);

class Ros2BagSource {
 public:
  Ros2BagSource(const std::filesystem::path& folder, const BagOptions& options);
  ~Ros2BagSource();

  std::size_t size() const { return stamps_.size(); }
  const std::vector<double>& stamps() const { return stamps_; }
  const std::vector<Eigen::Isometry3d>& poses() const { return poses_; }  // empty without a pose topic
  const std::string& topic() const { return topic_; }
  const std::string& storage() const { return info_.storage; }
  Scan read(std::size_t index, TimeUnit time_unit) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::filesystem::path folder_;
  Ros2BagInfo info_;
  std::string topic_;
  std::vector<double> stamps_;
  std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace cleanmap
