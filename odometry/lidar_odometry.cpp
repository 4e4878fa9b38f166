#include "odometry/lidar_odometry.hpp"

#include <chrono>

#include "io/error.hpp"
#include "io/voxel_downsample.hpp"
#include "odometry/deskew.hpp"
#include "odometry/point_to_plane_icp.hpp"
#include "odometry/preprocess.hpp"

namespace cleanmap {
namespace {

std::vector<Eigen::Vector3d> downsample(const Eigen::Matrix3Xf& points, double voxel) {
  const auto keep = voxel_downsample(points, voxel);
  std::vector<Eigen::Vector3d> out;
  out.reserve(keep.size());
  for (auto i : keep) out.push_back(points.col(i).cast<double>());
  return out;
}

double reference_fraction(const std::string& ref) {
  if (ref == "start") return 0.0;
  if (ref == "middle") return 0.5;
  return 1.0;
}

}  // namespace

void validate(const OdometryConfig& c) {
  auto bad = [](const std::string& what) { throw Error("odometry: " + what); };
  if (!(c.min_range >= 0) || !(c.max_range > c.min_range)) bad("need 0 <= min_range < max_range");
  if (!(c.map_voxel_size > 0)) bad("map_voxel_size must be positive");
  if (c.max_points_per_voxel < 1) bad("max_points_per_voxel must be >= 1");
  if (!(c.registration_voxel > 0)) bad("registration_voxel must be positive");
  if (!(c.initial_threshold > 0)) bad("initial_threshold must be positive");
  if (c.max_icp_iterations < 1 || c.solver_iterations < 1) bad("iteration counts must be >= 1");
  if (c.normal_neighbors < 3) bad("normal_neighbors must be >= 3");
  if (c.deskew_reference != "start" && c.deskew_reference != "middle" && c.deskew_reference != "end") {
    bad("deskew_reference must be start, middle or end, not '" + c.deskew_reference + "'");
  }
}

LidarOdometry::LidarOdometry(const OdometryConfig& config) : config_(config) {
  validate(config_);
  map_.voxel_size = config.map_voxel_size;
  map_.max_distance = config.map_radius;
  map_.max_points = config.max_points_per_voxel;
  threshold_.initial = config.initial_threshold;
  threshold_.min_motion = config.min_motion;
  threshold_.max_range = config.max_range;
}

OdometryStep LidarOdometry::register_scan(const Scan& scan) {
  const auto start = std::chrono::steady_clock::now();
  OdometryStep step;
  const std::size_t k = poses_.size();
  const double dt = k > 0 ? scan.stamp - stamps_.back() : 0.1;
  const double dt_prev = k > 1 ? stamps_[k - 1] - stamps_[k - 2] : dt;

  // Constant velocity: the last step's motion, scaled to this step's duration.
  Eigen::Isometry3d prediction = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_step = Eigen::Isometry3d::Identity();  // in the sensor frame, per dt
  if (k == 1) prediction = poses_[0];
  if (k > 1) {
    prediction = interpolate_pose(poses_[k - 2], poses_[k - 1], 1.0 + dt / dt_prev);
    last_step = poses_[k - 1].inverse() * prediction;
  }

  Scan pre = preprocess(scan, config_, dt > 0 ? dt : 0.1);
  const double sweep = pre.has_time() ? static_cast<double>(pre.time.maxCoeff()) : 0.0;
  step.reference_offset = pre.has_time() ? reference_fraction(config_.deskew_reference) * sweep : 0.0;
  if (config_.deskew && pre.has_time() && k > 1) {
    SweepMotion motion;
    motion.next = last_step;
    motion.dt = dt;
    pre = deskew(pre, motion, step.reference_offset);
  }
  step.points = pre.size();

  const Eigen::Matrix3Xf frame = pre.points(Eigen::all, voxel_downsample(pre.points, 0.5 * config_.map_voxel_size));
  // The registered points: the frame downsampled again (a quarter of the work of another pass
  // over the whole scan).
  const auto source = downsample(frame, config_.registration_voxel * config_.map_voxel_size);
  step.threshold = threshold_.value();
  step.pose = prediction;
  if (static_cast<int>(pre.size()) < config_.min_points) {
    step.degenerate = true;
    step.note = "too few points (" + std::to_string(pre.size()) + ")";
  } else if (!map_.empty()) {
    const auto r = method == "point_to_point"
                       ? register_point_to_point(source, map_, prediction, step.threshold, config_)
                       : register_point_to_plane(source, map_, prediction, step.threshold, config_);
    step.iterations = r.iterations;
    step.correspondences = r.correspondences;
    step.rms_residual = r.rms_residual;
    if (r.degenerate) {
      step.degenerate = true;
      step.note = "registration under-constrained (" + std::to_string(r.correspondences) + " matches)";
    } else {
      step.pose = r.pose;
      threshold_.update(prediction.inverse() * r.pose);
    }
  }
  if (!step.degenerate) {
    std::vector<Eigen::Vector3d> world;
    world.reserve(static_cast<std::size_t>(frame.cols()));
    for (Eigen::Index k = 0; k < frame.cols(); ++k) world.push_back(step.pose * frame.col(k).cast<double>());
    map_.add(world);
    map_.remove_far(step.pose.translation());
  }
  poses_.push_back(step.pose);
  stamps_.push_back(scan.stamp);
  step.deskewed = std::move(pre);
  step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return step;
}

std::size_t LidarOdometry::remove_dynamic(const std::vector<Eigen::Vector3d>& world_points) {
  return map_.remove_near(world_points, 0.5 * config_.map_voxel_size);
}

}  // namespace cleanmap
