#include "odometry/lidar_odometry.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "io/error.hpp"
#include "geometry/voxel_downsample.hpp"
#include "odometry/deskew.hpp"
#include "odometry/level_frame.hpp"
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

// Preprocessed; undistorted with `motion` (the sensor's motion over dt, in its own frame) when
// one is given and the scan has per-point times; then downsampled twice.
LidarOdometry::Prepared LidarOdometry::prepare(const Scan& scan, double dt,
                                               const Eigen::Isometry3d* motion) const {
  Prepared p;
  p.scan = preprocess(scan, config_, dt > 0 ? dt : 0.1);
  const double sweep = p.scan.has_time() ? static_cast<double>(p.scan.time.maxCoeff()) : 0.0;
  p.reference_offset = reference_fraction(config_.deskew_reference) * sweep;
  if (motion != nullptr && config_.deskew && p.scan.has_time()) {
    SweepMotion m;
    m.next = *motion;
    m.dt = dt;
    p.scan = deskew(p.scan, m, p.reference_offset);
  }
  p.frame = p.scan.points(Eigen::all, voxel_downsample(p.scan.points, 0.5 * config_.map_voxel_size));
  // The registered points: the frame downsampled again (a quarter of the work of another pass
  // over the whole scan).
  p.source = downsample(p.frame, config_.registration_voxel * config_.map_voxel_size);
  return p;
}

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
  if (k == 0 && config_.level_first_scan) {
    // The first pose is the levelling rotation: the map is built in the levelled world, so
    // every later pose, and every point the scorer feeds back, is in that one frame.
    if (const auto r = level_rotation(scan.points)) prediction.linear() = *r;
    else step.note = "level_first_scan: no dominant plane in the first scan; frame kept";
  }
  if (k == 1) prediction = poses_[0] * first_step_.value_or(Eigen::Isometry3d::Identity());
  if (k > 1) {
    prediction = interpolate_pose(poses_[k - 2], poses_[k - 1], 1.0 + dt / dt_prev);
    last_step = poses_[k - 1].inverse() * prediction;
  }
  const bool primed = k < 2 && first_step_.has_value();
  if (primed) last_step = *first_step_;

  Prepared p = prepare(scan, k == 0 && primed ? first_dt_ : dt, k > 1 || primed ? &last_step : nullptr);
  step.reference_offset = p.reference_offset;
  step.points = p.scan.size();
  step.threshold = threshold_.value();
  step.pose = prediction;
  if (static_cast<int>(p.scan.size()) < config_.min_points) {
    step.degenerate = true;
    step.note = "too few points (" + std::to_string(p.scan.size()) + ")";
  } else if (!map_.empty()) {
    const RegistrationResult r = register_prepared(scan, p, prediction, dt, step);
    step.correspondences = r.correspondences;
    step.rms_residual = r.rms_residual;
    step.inlier_share = r.inlier_share;
    if (r.degenerate) {
      step.degenerate = true;
      step.note = "registration under-constrained (" + std::to_string(r.correspondences) + " matches)";
    } else {
      step.pose = r.pose;
      threshold_.update(prediction.inverse() * r.pose);
      if (healthy(r)) remember_share(r.inlier_share);
    }
  }
  if (!step.degenerate) {
    std::vector<Eigen::Vector3d> world;
    world.reserve(static_cast<std::size_t>(p.frame.cols()));
    for (Eigen::Index k = 0; k < p.frame.cols(); ++k) world.push_back(step.pose * p.frame.col(k).cast<double>());
    map_.add(world);
    map_.remove_far(step.pose.translation());
  }
  poses_.push_back(step.pose);
  stamps_.push_back(scan.stamp);
  step.deskewed = std::move(p.scan);
  step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return step;
}

void LidarOdometry::prime(const Scan& first, const Scan& second) {
  if (!config_.deskew || !poses_.empty() || !(second.stamp > first.stamp)) return;
  LidarOdometry probe(config_);
  const OdometryStep a = probe.register_scan(first);
  const OdometryStep b = probe.register_scan(second);
  if (a.degenerate || b.degenerate) return;
  const Eigen::Isometry3d step = a.pose.inverse() * b.pose;
  if (step.translation().norm() < kStopGap && Eigen::AngleAxisd(step.rotation()).angle() < kStopTurn * M_PI / 180.0) {
    return;
  }
  first_step_ = step;
  first_dt_ = second.stamp - first.stamp;
  // The adaptive gate has always learnt the sensor's scale of motion from this step: predicted
  // as no motion, registered as `step`. Primed, the second scan's prediction is the step
  // itself and teaches it nothing, and the gate fell from 0.58 m to 0.11 m on the synthetic
  // street, too tight for its sparse far returns (matched shares 0.87 -> 0.30, lost at scan 16).
  threshold_.update(step);
}

// Registers `source` from `initial`; every registration's rounds count in step.iterations.
RegistrationResult LidarOdometry::align(const std::vector<Eigen::Vector3d>& source,
                                        const Eigen::Isometry3d& initial, const GateSchedule& gates,
                                        OdometryStep& step) const {
  const RegistrationResult r = method == "point_to_point"
                                   ? register_point_to_point(source, map_, initial, gates.end, config_)
                                   : register_point_to_plane(source, map_, initial, gates, config_);
  step.iterations += r.iterations;
  return r;
}

// From the prediction; over a long gap also from the previous pose; then the health check, and
// on failure the recovery, after which the sweep is undistorted with the motion found.
RegistrationResult LidarOdometry::register_prepared(const Scan& scan, Prepared& p,
                                                    const Eigen::Isometry3d& prediction, double dt,
                                                    OdometryStep& step) const {
  const GateSchedule adaptive{step.threshold, step.threshold};
  RegistrationResult r = align(p.source, prediction, adaptive, step);
  // Over a long gap the sensor may have stopped: a hard stop puts it up to a dt^2 / 2 from the
  // prediction (0.6 m over 0.5 s at 5 m/s^2). When that is more than the gate (the basin of the
  // registration from the prediction) and the previous pose is a start of its own (the
  // prediction moved away from it), register from the previous pose too and keep the larger
  // matched share. On balm (0.5 s gaps) this runs while the walk starts from rest, not once
  // the gate has grown with the walk's motion.
  const Eigen::Isometry3d predicted_step = poses_.back().inverse() * prediction;
  const bool distinct = predicted_step.translation().norm() > kStopGap ||
                        Eigen::AngleAxisd(predicted_step.rotation()).angle() > kStopTurn * M_PI / 180.0;
  if (distinct && 0.5 * kMaxAcceleration * dt * dt > std::max(kStopGap, step.threshold)) {
    const RegistrationResult still = align(p.source, poses_.back(), adaptive, step);
    if (!still.degenerate && (r.degenerate || still.inlier_share > r.inlier_share)) r = still;
  }
  if (healthy(r)) return r;
  r = recover(p.source, prediction, dt, step, r);
  if (step.recovered && config_.deskew && p.scan.has_time()) {
    // The sweep was undistorted with the predicted motion, which was wrong: undistort it
    // with the registered one (that sweep is what the map gets) and register once more.
    const Eigen::Isometry3d motion = poses_.back().inverse() * r.pose;
    p = prepare(scan, dt, &motion);
    const RegistrationResult redone = align(p.source, r.pose, adaptive, step);
    if (!redone.degenerate && redone.inlier_share >= r.inlier_share) r = redone;
  }
  return r;
}

// A registration is healthy when it settled and matched about as many of its points to map
// planes as the recent healthy scans did. A wrong minimum can have the smaller residual (it
// keeps only the matches that agree with it) but never the larger share: on the synthetic
// walk a registration caught by a turn matched 20-35% of its points against 80-90% before.
bool LidarOdometry::healthy(const RegistrationResult& r) const {
  if (r.degenerate || !r.converged) return false;
  if (recent_shares_.empty()) return true;
  std::vector<double> shares(recent_shares_.begin(), recent_shares_.end());
  std::nth_element(shares.begin(), shares.begin() + shares.size() / 2, shares.end());
  return r.inlier_share >= kHealthyShare * shares[shares.size() / 2];
}

void LidarOdometry::remember_share(double share) {
  recent_shares_.push_back(share);
  if (recent_shares_.size() > kShareHistory) recent_shares_.pop_front();
}

// Registers again with a wide first gate (the one used before any motion is known) narrowing
// to the adaptive one, from the prediction, from the previous pose (no motion), and from the
// previous pose turned about the sensor's z axis by every 10 deg up to what a turn of
// kMaxTurnRate could reach in dt (a wide gate's basin is about +-10 deg at 10 m). Keeps the
// result that matched the largest share of points (all end with the same gate, so the shares
// compare); `first` stays if none does better.
RegistrationResult LidarOdometry::recover(const std::vector<Eigen::Vector3d>& source,
                                          const Eigen::Isometry3d& prediction, double dt,
                                          OdometryStep& step, const RegistrationResult& first) const {
  const GateSchedule wide{std::max(config_.initial_threshold, step.threshold), step.threshold};
  std::vector<std::pair<std::string, Eigen::Isometry3d>> starts{{"prediction", prediction},
                                                                {"previous pose", poses_.back()}};
  const double reach = std::min(180.0, kMaxTurnRate * std::max(dt, 0.0));
  for (double deg = kTurnStep; deg < reach + kTurnStep; deg += kTurnStep) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::AngleAxisd turn(sign * deg * M_PI / 180.0, Eigen::Vector3d::UnitZ());
      starts.emplace_back("previous pose turned " + std::to_string(static_cast<int>(sign * deg)) + " deg",
                          poses_.back() * Eigen::Isometry3d(turn));
    }
  }
  RegistrationResult best = first;
  std::string from = "none";
  for (const auto& [name, initial] : starts) {
    const RegistrationResult r = align(source, initial, wide, step);
    if (r.degenerate || (!best.degenerate && r.inlier_share <= best.inlier_share)) continue;
    best = r;
    from = name;
  }
  char note[200];
  std::snprintf(note, sizeof note, "recovery: matched share %.2f -> %.2f (from %s)%s", first.inlier_share,
                best.inlier_share, from.c_str(), healthy(best) ? "" : ", still unhealthy");
  step.note = note;
  step.recovered = from != "none";
  return best;
}

std::size_t LidarOdometry::remove_dynamic(const std::vector<Eigen::Vector3d>& world_points) {
  return map_.remove_near(world_points, 0.5 * config_.map_voxel_size);
}

}  // namespace cleanmap
