#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/bag_common.hpp"
#include "io/cloud_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {


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
