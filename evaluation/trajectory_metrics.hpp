#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "io/pose_file.hpp"

namespace cleanmap {

// KITTI odometry benchmark errors, computed as the official devkit does
// (devkit/cpp/evaluate_odometry.cpp): segments of 100, 200, ..., 800 m of reference path length
// starting every 10 frames; per segment the relative-pose error over its length.
struct KittiSegmentError {
  int first_frame = 0;
  double length = 0.0;      // m
  double t_err = 0.0;       // translation error / length (multiply by 100 for %)
  double r_err = 0.0;       // rotation error / length, rad/m
};

struct KittiErrors {
  std::vector<KittiSegmentError> segments;
  std::vector<double> lengths;         // 100 ... 800
  std::vector<double> t_err_by_length; // % (NaN where no segment of that length fits)
  std::vector<double> r_err_by_length; // deg / 100 m
  double t_err_percent = 0.0;          // all segments pooled, as the leaderboard
  double r_err_deg_per_100m = 0.0;
};

KittiErrors kitti_errors(const std::vector<Eigen::Isometry3d>& reference,
                         const std::vector<Eigen::Isometry3d>& estimate);

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, max = 0;
  std::size_t count = 0;
};

ErrorStats error_stats(std::vector<double> errors);

enum class Alignment { kNone, kSE3, kSim3 };

// Absolute pose error of the translations after aligning the estimate to the reference
// (Umeyama, as evo's `evo_ape -a` / `-as`); returns the aligning transform too.
struct ApeResult {
  ErrorStats translation;
  Eigen::Matrix4d alignment = Eigen::Matrix4d::Identity();
  double scale = 1.0;
};
ApeResult absolute_pose_error(const std::vector<Eigen::Isometry3d>& reference,
                              const std::vector<Eigen::Isometry3d>& estimate, Alignment alignment);

// Relative pose error over `delta` frames (evo_rpe --delta N --delta_unit f).
struct RpeResult {
  ErrorStats translation;  // m
  ErrorStats rotation;     // deg
};
RpeResult relative_pose_error(const std::vector<Eigen::Isometry3d>& reference,
                              const std::vector<Eigen::Isometry3d>& estimate, int delta = 1);

// Pairs stamped poses by nearest stamp within `max_difference` seconds, in order, each
// reference used once (TUM's associate.py).
void associate(const std::vector<StampedPose>& reference, const std::vector<StampedPose>& estimate,
               double max_difference, std::vector<Eigen::Isometry3d>& ref_out,
               std::vector<Eigen::Isometry3d>& est_out);

// Pairs each estimated pose with the reference interpolated at its stamp, between the two
// reference poses around it when they are at most `max_gap` seconds apart (an estimate stamped
// mid-sweep, 0.05 s after a reference at the scan stamps, pairs; none is moved to a stamp).
// Estimates outside the reference's span pair with its end pose within `max_difference`.
void interpolate_reference(const std::vector<StampedPose>& reference, const std::vector<StampedPose>& estimate,
                           double max_gap, double max_difference, std::vector<Eigen::Isometry3d>& ref_out,
                           std::vector<Eigen::Isometry3d>& est_out);

// Angle (degrees) between the directions two trajectories move in, each in its own first frame,
// over the first `distance` metres the reference travels; NaN when either barely moves. Near
// 90 deg: the files are in different frames (KITTI: camera-0 against lidar).
double heading_difference_deg(const std::vector<Eigen::Isometry3d>& reference,
                              const std::vector<Eigen::Isometry3d>& estimate, double distance = 2.0);

}  // namespace cleanmap
