#pragma once

#include <string>

namespace cleanmap {

// Defaults work for a typical 10 Hz spinning lidar (KISS-ICP's choices where they apply).
struct OdometryConfig {
  double min_range = 1.0;            // m: closer returns are the vehicle itself
  double max_range = 100.0;          // m
  double map_voxel_size = 1.0;       // m; local-map voxels (KISS-ICP: max_range / 100)
  int max_points_per_voxel = 20;
  double map_radius = 100.0;         // m: voxels farther than this from the sensor are dropped
  double registration_voxel = 1.5;   // x map_voxel_size: downsampling of the registered points
  double initial_threshold = 2.0;    // m: correspondence distance before motion is observed
  double min_motion = 0.1;           // m: smaller steps do not update the adaptive threshold
  int max_icp_iterations = 100;      // cap on correspondence searches per scan (stops when settled)
  int solver_iterations = 5;         // Ceres iterations per correspondence set
  double convergence = 5e-4;         // stop when a step changes the pose less than this (m, rad)
  int normal_neighbors = 6;          // map points that define a local plane
  int min_points = 100;              // fewer points after preprocessing: degenerate scan
  bool deskew = true;                // undistort with the constant-velocity motion
  // Time a (deskewed) scan and its pose refer to: start, middle or end of the sweep. The middle
  // keeps the first scans, registered before any velocity is known and so not deskewed,
  // consistent with the rest: an uncorrected sweep is, on average, the sweep at its middle.
  std::string deskew_reference = "middle";
  bool time_from_azimuth = false;    // derive per-point times from azimuth when absent
  double vertical_correction_deg = 0.0;    // KITTI HDL-64: 0.205
  bool exclude_dynamic = false;      // drop scorer-labelled dynamic points from the local map
  // Rotate the odometry's world frame so the first scan's dominant plane is horizontal
  // (odometry/level_frame.hpp): a depth camera's first frame is not level, a lidar's is.
  bool level_first_scan = false;
};

}  // namespace cleanmap
