#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "io/pose_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {

// The sensor's motion over a sweep: pose at the scan stamp and the relative motion per second
// (as a pose delta expressed in the stamp's sensor frame), constant over the sweep.
struct SweepMotion {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();        // sensor -> world at stamp
  Eigen::Isometry3d next = Eigen::Isometry3d::Identity();        // sensor -> world at stamp + dt
  double dt = 0.1;                                               // seconds between the two
  Eigen::Isometry3d at(double t) const { return interpolate_pose(pose, next, t / dt); }
};

// The motion over sweep i of a sequence with known poses and times: towards the next pose, or
// for the last scan continuing the previous step (a single scan does not move).
SweepMotion sweep_motion(const std::vector<Eigen::Isometry3d>& poses,
                         const std::vector<double>& times, std::size_t i);

// Places every point in the world with the pose at its own capture time (scan.time); without
// per-point times every point uses the stamp's pose. Returns a world-frame copy (pose kept).
Scan to_world(const Scan& scan, const SweepMotion& motion);

// A sequence whose poses are known (each scan's pose at its stamp), every scan placed in the
// world with each point's pose at its own capture time (sweep_motion between neighbours).
std::vector<Scan> to_world(const std::vector<Scan>& scans);

// Scan i of a sequence (finite points, sensor frame, no per-point time: a spinning lidar's raw
// sweep) in the world frame, each point placed with the pose at its time from azimuth
// (times_from_azimuth, the sweep as long as the gap to the next stamp), counted from where the
// poses sit in their sweep: `pose_reference` of its last point's time (0.5: `run`'s mid-sweep
// poses). Raw scans put on a deskewing run's poses rigidly smear by up to half the sweep's
// travel (0.3 m at 6 m/s).
Eigen::Matrix3Xf place_by_azimuth(const Eigen::Matrix3Xf& points, const std::vector<Eigen::Isometry3d>& poses,
                                  const std::vector<double>& times, std::size_t i, double pose_reference);

// Undistorts a scan into the sensor frame at reference time `t_ref` (seconds relative to the
// stamp): p' = T(t_ref)^-1 T(t_i) p_i. A no-op without per-point times.
Scan deskew(const Scan& scan, const SweepMotion& motion, double t_ref);

}  // namespace cleanmap
