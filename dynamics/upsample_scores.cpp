#include "dynamics/upsample_scores.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "io/point_index.hpp"

namespace cleanmap {

PointDecisions upsample_scores(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                               const PointDecisions& d, const std::string& method,
                               double radius) {
  const auto n = static_cast<std::size_t>(full.cols());
  PointDecisions out;
  out.score.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.dynamic.assign(n, 0);
  if (down.cols() == 0) return out;
  const PointIndex all(down);
  const float r_sq = static_cast<float>(radius * radius);

  // For "paper", an index over the dynamic downsampled points only.
  Eigen::Matrix3Xf dyn_points;
  if (method == "paper") {
    std::vector<Eigen::Index> dyn;
    for (std::size_t i = 0; i < d.dynamic.size(); ++i) {
      if (d.dynamic[i]) dyn.push_back(static_cast<Eigen::Index>(i));
    }
    dyn_points.resize(3, static_cast<Eigen::Index>(dyn.size()));
    for (std::size_t k = 0; k < dyn.size(); ++k) dyn_points.col(static_cast<Eigen::Index>(k)) = down.col(dyn[k]);
  }
  const PointIndex dynamic_index(dyn_points);

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f p = full.col(static_cast<Eigen::Index>(i));
      const auto nn = all.nearest(p);
      if (nn && nn->second <= r_sq) {
        out.score[i] = d.score[nn->first];
        if (method != "paper") out.dynamic[i] = d.dynamic[nn->first];
      }
      if (method == "paper") {
        const auto dn = dynamic_index.nearest(p);
        out.dynamic[i] = (dn && dn->second <= r_sq) ? 1 : 0;
      }
    }
  });
  return out;
}

}  // namespace cleanmap
