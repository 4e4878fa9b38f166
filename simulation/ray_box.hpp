#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace cleanmap {

// Distance along `d` from `o` to where the ray enters the axis-aligned box [lo, hi] (slab
// method), or infinity when it misses or starts inside. Both simulators' boxes use it.
inline double ray_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double s_in = -kInf, s_out = kInf;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
      continue;
    }
    double s1 = (lo[k] - o[k]) / d[k], s2 = (hi[k] - o[k]) / d[k];
    if (s1 > s2) std::swap(s1, s2);
    s_in = std::max(s_in, s1);
    s_out = std::min(s_out, s2);
  }
  if (s_in > s_out || s_out <= 0) return kInf;
  return s_in > 0 ? s_in : kInf;
}

}  // namespace cleanmap
