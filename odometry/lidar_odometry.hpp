#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "io/scan.hpp"
#include "odometry/adaptive_threshold.hpp"
#include "odometry/odometry_config.hpp"
#include "odometry/point_to_plane_icp.hpp"
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
  double inlier_share = 0.0;  // registered points lying on a map plane (see Health)
  double threshold = 0.0;
  std::size_t points = 0;   // after preprocessing
  bool degenerate = false;  // pose fell back to the motion prior; scan not added to the map
  bool recovered = false;   // the first registration failed the health check; re-registered
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

  // Before the first scan: the first step, registered between the first two sweeps as they
  // are, becomes the motion both are undistorted with. Without it nothing tells the motion
  // over them: a sensor at 5 m/s smears each by 0.5 m, and the scorer sees the smear as motion
  // (the static synthetic street with our odometry: 381 -> 52 false points offline, 1407 ->
  // 400 online). A step under kStopGap and kStopTurn is left out (nothing to undistort), as is
  // every call after the first scan or with deskewing off.
  void prime(const Scan& first, const Scan& second);

  // Feedback from the scorer: removes local-map points near these world points (the scorer
  // reports N scans late, so this cleans the map for later scans, not the scan just scored).
  std::size_t remove_dynamic(const std::vector<Eigen::Vector3d>& world_points);

  const std::vector<Eigen::Isometry3d>& poses() const { return poses_; }
  const VoxelHashMap& local_map() const { return map_; }

  // "point_to_plane" (default) or "point_to_point" (the benchmark's baseline).
  std::string method = "point_to_plane";

  // Healthy: matched share >= kHealthyShare x the median of the last kShareHistory healthy
  // scans (on healthy real and synthetic scans it varies by +-10%; a caught registration halves).
  static constexpr double kHealthyShare = 0.75;
  static constexpr std::size_t kShareHistory = 10;
  // Recovery tries turns up to this rate (deg/s; a brisk hand-held turn is 60-90) in steps of
  // kTurnStep deg.
  static constexpr double kMaxTurnRate = 90.0;
  static constexpr double kTurnStep = 10.0;
  // m/s^2: hard braking of a car (0.5 g); walkers and robots change speed more gently.
  static constexpr double kMaxAcceleration = 5.0;
  // A stop that moves the sensor less than kStopGap (m) or turns it less than kStopTurn (deg)
  // from the prediction needs no second registration: the first starts within the basin of
  // any gate (at 10 Hz a hard stop is 2.5 cm).
  static constexpr double kStopGap = 0.1;
  static constexpr double kStopTurn = 1.0;

 private:
  // A scan made ready for registration.
  struct Prepared {
    Scan scan;                            // preprocessed (and undistorted), sensor frame
    double reference_offset = 0.0;        // s after the stamp that the pose refers to
    Eigen::Matrix3Xf frame;               // downsampled to half a map voxel: enters the map
    std::vector<Eigen::Vector3d> source;  // downsampled again: the registered points
  };
  Prepared prepare(const Scan& scan, double dt, const Eigen::Isometry3d* motion) const;
  RegistrationResult register_prepared(const Scan& scan, Prepared& p, const Eigen::Isometry3d& prediction,
                                       double dt, OdometryStep& step) const;
  RegistrationResult align(const std::vector<Eigen::Vector3d>& source, const Eigen::Isometry3d& initial,
                           const GateSchedule& gates, OdometryStep& step) const;
  bool healthy(const RegistrationResult& r) const;
  void remember_share(double share);
  RegistrationResult recover(const std::vector<Eigen::Vector3d>& source, const Eigen::Isometry3d& prediction,
                             double dt, OdometryStep& step, const RegistrationResult& first) const;

  OdometryConfig config_;
  VoxelHashMap map_;
  AdaptiveThreshold threshold_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<double> stamps_;
  std::deque<double> recent_shares_;  // matched shares of the last healthy registrations
  std::optional<Eigen::Isometry3d> first_step_;  // prime(): the motion over the first step
  double first_dt_ = 0.1;                        // s, the first step's duration
};

void validate(const OdometryConfig& config);

}  // namespace cleanmap
