#include "mapping/visibility_around.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>
#include <tsl/robin_set.h>

#include "geometry/voxel_key.hpp"

namespace cleanmap {
namespace {

using CellSet3 = tsl::robin_set<VoxelKey, VoxelKeyHash>;

// The cells of `points`.
CellSet3 cells_of(const Eigen::Matrix3Xf& points, double inv) {
  CellSet3 cells;
  for (Eigen::Index i = 0; i < points.cols(); ++i) cells.insert(voxel_of(points.col(i), inv));
  return cells;
}

// Directions from one origin in 1-degree bins of azimuth and elevation, each with the nearest
// range at which a cell of interest lies along it.
class DirectionBins {
 public:
  static constexpr int kAz = 360, kEl = 180;
  DirectionBins() : near_(static_cast<std::size_t>(kAz) * kEl, std::numeric_limits<float>::infinity()) {}

  // A ball of `radius` around `centre`, seen from the origin (`rel` = centre - origin).
  void mark(const Eigen::Vector3d& rel, double radius) {
    const double r = rel.norm();
    if (!(r > radius)) {  // the origin inside it: every direction
      std::fill(near_.begin(), near_.end(), 0.0f);
      return;
    }
    const double half = std::asin(radius / r) * kDeg;  // the ball's angular radius, degrees
    const double az = azimuth(rel), el = elevation(rel);
    const int e0 = std::max(0, static_cast<int>(std::floor(el - half)) + 90);
    const int e1 = std::min(kEl - 1, static_cast<int>(std::floor(el + half)) + 90);
    // Azimuth spreads by 1 / cos(elevation); near a pole, every azimuth.
    const double cos_el = std::cos((std::abs(el) + half) / kDeg);
    const double spread = cos_el > 1e-3 ? half / cos_el : 180.0;
    const int a0 = static_cast<int>(std::floor(az - spread)), a1 = static_cast<int>(std::floor(az + spread));
    const auto nearest = static_cast<float>(r - radius);
    for (int e = e0; e <= e1; ++e) {
      for (int a = a0; a <= std::min(a1, a0 + kAz - 1); ++a) {
        float& n = near_[static_cast<std::size_t>(e) * kAz + static_cast<std::size_t>(((a % kAz) + kAz) % kAz)];
        n = std::min(n, nearest);
      }
    }
  }
  // Whether a ray to `rel` (point - origin) can pass a marked ball.
  bool reaches(const Eigen::Vector3d& rel) const {
    const int a = std::clamp(static_cast<int>(std::floor(azimuth(rel))), 0, kAz - 1);
    const int e = std::clamp(static_cast<int>(std::floor(elevation(rel))) + 90, 0, kEl - 1);
    return rel.norm() >= near_[static_cast<std::size_t>(e) * kAz + static_cast<std::size_t>(a)];
  }

 private:
  static constexpr double kDeg = 180.0 / M_PI;
  static double azimuth(const Eigen::Vector3d& v) {
    const double a = std::atan2(v.y(), v.x()) * kDeg;
    return a < 0 ? a + 360.0 : a;
  }
  static double elevation(const Eigen::Vector3d& v) { return std::atan2(v.z(), v.head<2>().norm()) * kDeg; }
  std::vector<float> near_;
};

}  // namespace

VisibilityMap visibility_around(const Eigen::Matrix3Xf& around, const std::vector<ScanView>& scans,
                                const VisibilityConfig& config) {
  VisibilityMap map(config);
  const double res = config.resolution, inv = 1.0 / res;
  const CellSet3 target = cells_of(around, inv);
  // A ray crosses a cell when it passes within its half diagonal of the centre; one more cell
  // covers the ray's start a margin short of its point and its subsampling to one point per
  // cell, and the sensor's travel over the sweep covers rays cast from where it was then.
  const double reach_radius = 0.5 * std::sqrt(3.0) * res + res;
  // Each scan's rays that can pass the cells of interest, and later their casts, side by side
  // (cast is const); hits and counts go in scan order, as they number the scans. An online run
  // judges its first and last scans with this in the scoring stage, which every other stage
  // waits for: one after another, the scans' bins and casts were 1.7 s of the 9 s that the
  // Pandar64 street took online.
  // The scans' hits too (hits_of: their cells and boxes), added in scan order after: added one
  // scan after another, they were 0.4 s of the street's first scan's 0.9 s judgement.
  std::vector<Eigen::Matrix3Xf> rays(scans.size());
  std::vector<Eigen::VectorXf> ray_times(scans.size());
  std::vector<VisibilityMap::ScanHits> hits(scans.size());
  tbb::parallel_for(std::size_t{0}, scans.size(), [&](std::size_t s) {
    const ScanView& v = scans[s];
    hits[s] = map.hits_of(*v.points, v.origin);
    const Eigen::Matrix3Xf& p = *v.points;
    const bool timed = v.times != nullptr && v.times->size() == p.cols() && p.cols() > 0;
    const double t0 = timed ? static_cast<double>(v.times->minCoeff()) : 0.0;
    const double t1 = timed ? static_cast<double>(v.times->maxCoeff()) : 0.0;
    const double travel = std::max((v.sensor.at(t0) - v.origin).norm(), (v.sensor.at(t1) - v.origin).norm());
    const double radius = reach_radius + (std::isfinite(travel) ? travel : 0.0);
    DirectionBins bins;
    for (const auto& k : target) {
      const Eigen::Vector3d centre = (Eigen::Vector3d(k.x, k.y, k.z) + Eigen::Vector3d::Constant(0.5)) * res;
      bins.mark(centre - v.origin, radius);
    }
    std::vector<Eigen::Index> reach;
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      if (bins.reaches(p.col(i).cast<double>() - v.origin)) reach.push_back(i);
    }
    rays[s] = p(Eigen::all, reach);
    if (timed) ray_times[s] = (*v.times)(reach);
  });
  for (auto& h : hits) {
    map.add_hits(h);
    h = {};
  }
  map.fit_surfaces();
  std::vector<VisibilityMap::ScanRays> cast(scans.size());
  tbb::parallel_for(std::size_t{0}, scans.size(),
                    [&](std::size_t s) { cast[s] = map.cast(rays[s], ray_times[s], scans[s].sensor); });
  for (const auto& c : cast) map.count(c);
  return map;
}

}  // namespace cleanmap
