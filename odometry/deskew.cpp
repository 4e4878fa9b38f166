#include "odometry/deskew.hpp"

#include "odometry/preprocess.hpp"

#include <tbb/parallel_for.h>

#include <limits>

namespace cleanmap {

SweepMotion sweep_motion(const std::vector<Eigen::Isometry3d>& poses,
                         const std::vector<double>& times, std::size_t i) {
  SweepMotion m;
  m.pose = poses.at(i);
  if (i + 1 < poses.size()) {
    m.next = poses[i + 1];
    m.dt = times.at(i + 1) - times.at(i);
  } else if (i > 0) {
    m.next = poses[i] * (poses[i - 1].inverse() * poses[i]);
    m.dt = times.at(i) - times.at(i - 1);
  } else {
    m.next = poses[i];
    m.dt = 1.0;
  }
  return m;
}

namespace {

// Applies T_ref^-1 * T(t_i) to every point (T_ref = identity for world placement).
Scan transform_per_point(const Scan& scan, const SweepMotion& motion,
                         const Eigen::Isometry3d& ref_inverse) {
  Scan out = scan;
  if (!scan.has_time()) {
    out.points = ((ref_inverse * motion.pose).cast<float>() * scan.points);
    return out;
  }
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, scan.points.cols(), 4096), [&](const auto& r) {
    // Spinning lidars stamp a whole firing (a column of points) with one time: interpolate a
    // pose once per distinct time, not once per point.
    float last_time = std::numeric_limits<float>::quiet_NaN();
    Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
    for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
      if (scan.time[i] != last_time) {
        last_time = scan.time[i];
        t = (ref_inverse * motion.at(last_time)).cast<float>();
      }
      out.points.col(i) = t * scan.points.col(i);
    }
  });
  return out;
}

}  // namespace

Scan to_world(const Scan& scan, const SweepMotion& motion) {
  Scan out = transform_per_point(scan, motion, Eigen::Isometry3d::Identity());
  out.pose = motion.pose;
  return out;
}

std::vector<Scan> to_world(const std::vector<Scan>& scans) {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<double> times;
  for (const auto& s : scans) {
    poses.push_back(s.pose.value());
    times.push_back(s.stamp);
  }
  std::vector<Scan> out;
  for (std::size_t i = 0; i < scans.size(); ++i) out.push_back(to_world(scans[i], sweep_motion(poses, times, i)));
  return out;
}

Eigen::Matrix3Xf place_by_azimuth(const Eigen::Matrix3Xf& points, const std::vector<Eigen::Isometry3d>& poses,
                                  const std::vector<double>& times, std::size_t i, double pose_reference) {
  if (points.cols() == 0) return points;
  const std::size_t n = times.size();
  const double sweep = i + 1 < n ? times[i + 1] - times[i] : i > 0 ? times[i] - times[i - 1] : 0.1;
  Scan scan;
  scan.points = points;
  scan.time = times_from_azimuth(points, sweep);
  scan.time.array() -= static_cast<float>(pose_reference) * scan.time.maxCoeff();
  return to_world(scan, sweep_motion(poses, times, i)).points;
}

Scan deskew(const Scan& scan, const SweepMotion& motion, double t_ref) {
  if (!scan.has_time()) return scan;
  return transform_per_point(scan, motion, motion.at(t_ref).inverse());
}

}  // namespace cleanmap
