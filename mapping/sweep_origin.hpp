#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "io/pose_file.hpp"

namespace cleanmap {

// Where a spinning sensor was while it swept one scan: at `start` at the scan's stamp (time 0
// of its per-point times), moving at `velocity` (world frame, m/s), straight over the sweep (a
// 0.1 s sweep turns a car by a degree or two: its path bends by millimetres).
// A ray belongs to where the sensor was when it fired: at 5 m/s the sensor moves 0.5 m over a
// sweep, and rays cast from the stamp's origin for the whole sweep swung by up to that much at
// the sensor's end. On the static synthetic street with given poses (poses at the sweep's
// start), rays to a building behind a parked car, cast so, passed 2-10 cm inside the car's
// front face and went through it in 1-3 of the 21-28 scans that hit it. bench/quality.sh is
// unchanged by it on every set (it only moves rays of scans with per-point times).
struct SweepOrigin {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d at(double t) const { return start + velocity * t; }
};

// Scan i's, from the log's poses (poses[i] is scan i's, at its own time: the stamp with given
// poses, mid-sweep with odometry's) and the scan's stamp: the velocity of its neighbours'
// positions (central, one-sided at the log's ends), the start extrapolated back from pose i.
// Standing still (velocity zero) where the neighbours' times do not increase or are not finite,
// or where the log has one scan.
SweepOrigin sweep_origin(const std::vector<StampedPose>& poses, std::size_t i, double stamp);

}  // namespace cleanmap
