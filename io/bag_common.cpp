#include "io/bag_common.hpp"

#include "io/error.hpp"
#include "io/pose_file.hpp"

namespace cleanmap {

std::optional<Eigen::Isometry3d> checked_pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  if (!q.coeffs().allFinite() || !t.allFinite() || !(q.norm() > 1e-6)) return std::nullopt;
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = t;
  return p;
}

void check_coverage(const std::filesystem::path& source, const std::map<double, Eigen::Isometry3d>& track,
                    const std::vector<double>& times, const std::string& what, const std::string& advice) {
  const double gap = times.size() > 1 ? (times.back() - times.front()) / static_cast<double>(times.size() - 1) : 0.0;
  const double lo = track.begin()->first - 0.5 * gap, hi = track.rbegin()->first + 0.5 * gap;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (times[i] < lo || times[i] > hi) {
      fail(source, "poses cover " + std::to_string(track.begin()->first) + " to " +
                       std::to_string(track.rbegin()->first) + " s, but " + what + " " + std::to_string(i) +
                       " is at " + std::to_string(times[i]) + " s: " + advice);
    }
  }
}

Eigen::Isometry3d pose_at(const std::map<double, Eigen::Isometry3d>& track, double t) {
  auto hi = track.lower_bound(t);
  if (hi == track.begin()) return hi->second;
  if (hi == track.end()) return std::prev(hi)->second;
  auto lo = std::prev(hi);
  return interpolate_pose(lo->second, hi->second, (t - lo->first) / (hi->first - lo->first));
}

}  // namespace cleanmap
