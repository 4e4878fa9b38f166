#include "evaluation/map_metrics.hpp"

#include <tbb/parallel_for.h>

#include <cmath>

#include "geometry/point_index.hpp"

namespace cleanmap {
namespace {

// 1 where `cloud` has a point within `distance` of `queries`' column (squared distance).
std::vector<std::uint8_t> near_points(const Eigen::Matrix3Xf& queries, const Eigen::Matrix3Xf& cloud,
                                      double distance) {
  const PointIndex index(cloud);
  const auto n = static_cast<std::size_t>(queries.cols());
  std::vector<std::uint8_t> near(n, 0);
  const double d_sq = distance * distance;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const auto nn = index.nearest(queries.col(static_cast<Eigen::Index>(i)));
      near[i] = nn && nn->second <= d_sq;
    }
  });
  return near;
}

}  // namespace

MapScore score_map(const Eigen::Matrix3Xf& gt, const std::vector<std::uint8_t>& dynamic,
                   const Eigen::Matrix3Xf& output, double distance) {
  const auto n = static_cast<std::size_t>(gt.cols());
  const auto kept = near_points(gt, output, distance);
  MapScore s;
  for (std::size_t i = 0; i < n; ++i) {
    if (dynamic[i]) {
      ++s.dynamic_points;
      s.dynamic_removed += !kept[i];
    } else {
      ++s.static_points;
      s.static_kept += kept[i];
    }
  }
  s.sa = s.static_points ? 100.0 * static_cast<double>(s.static_kept) / static_cast<double>(s.static_points) : NAN;
  s.da = s.dynamic_points ? 100.0 * static_cast<double>(s.dynamic_removed) / static_cast<double>(s.dynamic_points) : NAN;
  s.aa = std::sqrt(s.sa * s.da);
  std::vector<Eigen::Index> moving, standing;
  for (std::size_t i = 0; i < n; ++i) (dynamic[i] ? moving : standing).push_back(static_cast<Eigen::Index>(i));
  const auto shadowed = near_points(gt(Eigen::all, moving), gt(Eigen::all, standing), distance);
  std::size_t clear = 0;
  for (const auto c : shadowed) clear += !c;
  s.da_ceiling = s.dynamic_points ? 100.0 * static_cast<double>(clear) / static_cast<double>(s.dynamic_points) : NAN;
  s.ha = (s.sa + s.da) > 0 ? 2.0 * s.sa * s.da / (s.sa + s.da) : NAN;
  return s;
}

}  // namespace cleanmap
