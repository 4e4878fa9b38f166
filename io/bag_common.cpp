#include "io/bag_common.hpp"

#include "io/pose_file.hpp"

namespace cleanmap {

std::optional<Eigen::Isometry3d> checked_pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  if (!q.coeffs().allFinite() || !t.allFinite() || !(q.norm() > 1e-6)) return std::nullopt;
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = t;
  return p;
}

Eigen::Isometry3d pose_at(const std::map<double, Eigen::Isometry3d>& track, double t) {
  auto hi = track.lower_bound(t);
  if (hi == track.begin()) return hi->second;
  if (hi == track.end()) return std::prev(hi)->second;
  auto lo = std::prev(hi);
  return interpolate_pose(lo->second, hi->second, (t - lo->first) / (hi->first - lo->first));
}

}  // namespace cleanmap
