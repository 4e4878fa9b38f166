#include "evaluation/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/error.hpp"

namespace cleanmap {
namespace {

double rotation_angle(const Eigen::Isometry3d& e) {
  const double d = 0.5 * (e.linear().trace() - 1.0);
  return std::acos(std::max(std::min(d, 1.0), -1.0));
}

void check_sizes(std::size_t a, std::size_t b) {
  if (a != b || a == 0) {
    throw Error("trajectories differ in length (" + std::to_string(a) + " reference poses, " +
                std::to_string(b) + " estimated)");
  }
}

}  // namespace

KittiErrors kitti_errors(const std::vector<Eigen::Isometry3d>& ref,
                         const std::vector<Eigen::Isometry3d>& est) {
  check_sizes(ref.size(), est.size());
  KittiErrors out;
  out.lengths = {100, 200, 300, 400, 500, 600, 700, 800};
  std::vector<double> dist(ref.size(), 0.0);
  for (std::size_t i = 1; i < ref.size(); ++i) {
    dist[i] = dist[i - 1] + (ref[i].translation() - ref[i - 1].translation()).norm();
  }
  const std::size_t step = 10;
  for (std::size_t first = 0; first < ref.size(); first += step) {
    for (double len : out.lengths) {
      std::size_t last = first;
      while (last < ref.size() && !(dist[last] > dist[first] + len)) ++last;
      if (last >= ref.size()) continue;
      const Eigen::Isometry3d delta_ref = ref[first].inverse() * ref[last];
      const Eigen::Isometry3d delta_est = est[first].inverse() * est[last];
      const Eigen::Isometry3d e = delta_est.inverse() * delta_ref;
      out.segments.push_back({static_cast<int>(first), len, e.translation().norm() / len,
                              rotation_angle(e) / len});
    }
  }
  double t_sum = 0, r_sum = 0;
  for (const auto& s : out.segments) {
    t_sum += s.t_err;
    r_sum += s.r_err;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(out.segments.size());
  out.t_err_percent = out.segments.empty() ? nan : 100.0 * t_sum / n;
  out.r_err_deg_per_100m = out.segments.empty() ? nan : 100.0 * (180.0 / M_PI) * r_sum / n;
  for (double len : out.lengths) {
    double t = 0, r = 0;
    int k = 0;
    for (const auto& s : out.segments) {
      if (s.length != len) continue;
      t += s.t_err;
      r += s.r_err;
      ++k;
    }
    out.t_err_by_length.push_back(k ? 100.0 * t / k : nan);
    out.r_err_by_length.push_back(k ? 100.0 * (180.0 / M_PI) * r / k : nan);
  }
  return out;
}

ErrorStats error_stats(std::vector<double> e) {
  ErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  double sq = 0, sum = 0;
  for (double v : e) {
    sq += v * v;
    sum += v;
    s.max = std::max(s.max, v);
  }
  s.rmse = std::sqrt(sq / static_cast<double>(e.size()));
  s.mean = sum / static_cast<double>(e.size());
  std::sort(e.begin(), e.end());
  const std::size_t m = e.size() / 2;
  s.median = e.size() % 2 ? e[m] : 0.5 * (e[m - 1] + e[m]);
  return s;
}

ApeResult absolute_pose_error(const std::vector<Eigen::Isometry3d>& ref,
                              const std::vector<Eigen::Isometry3d>& est, Alignment alignment) {
  check_sizes(ref.size(), est.size());
  ApeResult out;
  const auto n = static_cast<Eigen::Index>(ref.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = est[static_cast<std::size_t>(i)].translation();
    dst.col(i) = ref[static_cast<std::size_t>(i)].translation();
  }
  if (alignment != Alignment::kNone && n >= 3) {
    out.alignment = Eigen::umeyama(src, dst, alignment == Alignment::kSim3);
    out.scale = out.alignment.block<3, 1>(0, 0).norm();
  }
  std::vector<double> errors;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d aligned = (out.alignment * src.col(i).homogeneous()).head<3>();
    errors.push_back((aligned - dst.col(i)).norm());
  }
  out.translation = error_stats(errors);
  return out;
}

RpeResult relative_pose_error(const std::vector<Eigen::Isometry3d>& ref,
                              const std::vector<Eigen::Isometry3d>& est, int delta) {
  check_sizes(ref.size(), est.size());
  if (delta < 1) throw Error("RPE delta must be at least one frame");
  std::vector<double> t, r;
  for (std::size_t i = 0; i + static_cast<std::size_t>(delta) < ref.size(); ++i) {
    const std::size_t j = i + static_cast<std::size_t>(delta);
    const Eigen::Isometry3d e = (ref[i].inverse() * ref[j]).inverse() * (est[i].inverse() * est[j]);
    t.push_back(e.translation().norm());
    r.push_back(rotation_angle(e) * 180.0 / M_PI);
  }
  return {error_stats(t), error_stats(r)};
}

void associate(const std::vector<StampedPose>& ref, const std::vector<StampedPose>& est,
               double max_difference, std::vector<Eigen::Isometry3d>& ref_out,
               std::vector<Eigen::Isometry3d>& est_out) {
  ref_out.clear();
  est_out.clear();
  std::size_t j = 0;
  for (const auto& e : est) {
    while (j + 1 < ref.size() && std::abs(ref[j + 1].stamp - e.stamp) <= std::abs(ref[j].stamp - e.stamp)) ++j;
    if (j < ref.size() && std::abs(ref[j].stamp - e.stamp) <= max_difference) {
      ref_out.push_back(ref[j].pose);
      est_out.push_back(e.pose);
      ++j;  // each reference pose once
    }
  }
}

void interpolate_reference(const std::vector<StampedPose>& ref, const std::vector<StampedPose>& est, double max_gap,
                           double max_difference, std::vector<Eigen::Isometry3d>& ref_out,
                           std::vector<Eigen::Isometry3d>& est_out) {
  ref_out.clear();
  est_out.clear();
  if (ref.empty()) return;
  std::size_t j = 0;
  for (const auto& e : est) {
    while (j + 1 < ref.size() && ref[j + 1].stamp <= e.stamp) ++j;
    if (e.stamp < ref.front().stamp || e.stamp >= ref.back().stamp) {
      const auto& end = e.stamp < ref.front().stamp ? ref.front() : ref.back();
      if (std::abs(end.stamp - e.stamp) > max_difference) continue;
      ref_out.push_back(end.pose);
    } else {
      const auto& lo = ref[j];
      const auto& hi = ref[j + 1];
      if (hi.stamp - lo.stamp > max_gap) continue;
      const double f = hi.stamp > lo.stamp ? (e.stamp - lo.stamp) / (hi.stamp - lo.stamp) : 0.0;
      ref_out.push_back(interpolate_pose(lo.pose, hi.pose, f));
    }
    est_out.push_back(e.pose);
  }
}

double heading_difference_deg(const std::vector<Eigen::Isometry3d>& ref, const std::vector<Eigen::Isometry3d>& est,
                              double distance) {
  const std::size_t n = std::min(ref.size(), est.size());
  for (std::size_t k = 1; k < n; ++k) {
    const Eigen::Vector3d r = ref[0].inverse() * ref[k].translation();
    if (r.norm() < distance) continue;
    const Eigen::Vector3d e = est[0].inverse() * est[k].translation();
    if (e.norm() < 0.5 * distance) return std::nan("");
    return std::acos(std::clamp(r.normalized().dot(e.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
  }
  return std::nan("");
}

}  // namespace cleanmap
