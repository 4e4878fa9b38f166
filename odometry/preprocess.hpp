#pragma once

#include "io/scan.hpp"
#include "odometry/odometry_config.hpp"

namespace cleanmap {

// Range crop, KITTI's vertical-angle correction and (optionally) per-point times from azimuth,
// in the sensor frame. Non-finite points must already be dropped.
Scan preprocess(const Scan& scan, const OdometryConfig& config, double sweep_seconds);

// Per-point times for a spinning lidar that turns clockwise (seen from above) once per
// `sweep_seconds`, its points stored in firing order, column after column (as Hesai and
// Velodyne drivers write them; not for ring-after-ring clouds): the angle turned since the
// first point, unwrapped along the storage order. So the sweep starts wherever the driver cut
// it (the Pandar64 street's scans start near +45 deg: counting from +x put the points between
// +x and the cut a whole sweep late, 0.6 m at 6 m/s), and a scan that turns past a full
// revolution (those scans end 30 deg past their start) keeps its last points' times past
// `sweep_seconds` instead of wrapping them to its start.
Eigen::VectorXf times_from_azimuth(const Eigen::Matrix3Xf& points, double sweep_seconds);

}  // namespace cleanmap
