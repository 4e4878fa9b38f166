#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "io/scan.hpp"
#include "odometry/adaptive_threshold.hpp"
#include "odometry/odometry_config.hpp"
#include "odometry/voxel_hash_map.hpp"

namespace cleanmap {

// What one scan did to the odometry: its pose and a log line's worth of numbers.
struct OdometryStep {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // sensor -> world at reference time
  Scan deskewed;            // preprocessed, undistorted scan, sensor frame at the reference time
  double reference_offset = 0.0;  // seconds after the scan stamp that `pose` refers to
  int iterations = 0;
  int correspondences = 0;
  double rms_residual = 0.0;
  double threshold = 0.0;
  std::size_t points = 0;   // after preprocessing
  bool degenerate = false;  // pose fell back to the motion prior; scan not added to the map
  std::string note;
  double seconds = 0.0;
};

// Scan-to-local-map lidar odometry: constant-velocity prediction, deskewing, point-to-plane
// registration (Ceres) against a voxel-hash local map with an adaptive correspondence threshold.
class LidarOdometry {
 public:
  explicit LidarOdometry(const OdometryConfig& config);

  // `scan`: sensor frame, non-finite points dropped, stamp set, per-point time optional.
  OdometryStep register_scan(const Scan& scan);

  // Feedback from the scorer: removes local-map points near these world points (the scorer
  // reports N scans late, so this cleans the map for later scans, not the scan just scored).
  std::size_t remove_dynamic(const std::vector<Eigen::Vector3d>& world_points);

  const std::vector<Eigen::Isometry3d>& poses() const { return poses_; }
  const VoxelHashMap& local_map() const { return map_; }

  // "point_to_plane" (default) or "point_to_point" (the benchmark's baseline).
  std::string method = "point_to_plane";

 private:
  OdometryConfig config_;
  VoxelHashMap map_;
  AdaptiveThreshold threshold_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<double> stamps_;
};

void validate(const OdometryConfig& config);

}  // namespace cleanmap
