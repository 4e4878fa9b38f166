#pragma once

#include "io/scan.hpp"
#include "odometry/odometry_config.hpp"

namespace cleanmap {

// Range crop, KITTI's vertical-angle correction and (optionally) per-point times from azimuth,
// in the sensor frame. Non-finite points must already be dropped.
Scan preprocess(const Scan& scan, const OdometryConfig& config, double sweep_seconds);

// Per-point times for a spinning lidar that turns clockwise (seen from above) starting at +x
// (Velodyne, Ouster, Hesai), one revolution per sweep.
Eigen::VectorXf times_from_azimuth(const Eigen::Matrix3Xf& points, double sweep_seconds);

}  // namespace cleanmap
