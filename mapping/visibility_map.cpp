#include "mapping/visibility_map.hpp"

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "io/error.hpp"
#include "geometry/voxel_downsample.hpp"
#include "mapping/carve_ray.hpp"

namespace cleanmap {
namespace {

constexpr std::uint16_t kMaxCount = std::numeric_limits<std::uint16_t>::max();

void bump(std::uint16_t& c) { c = static_cast<std::uint16_t>(std::min<int>(c + 1, kMaxCount)); }

}  // namespace

void validate(const VisibilityConfig& c) {
  auto bad = [](const std::string& what) { throw Error("visibility: " + what); };
  if (!std::isfinite(c.resolution) || !(c.resolution > 0)) bad("visibility_resolution must be positive");
  if (!std::isfinite(c.margin) || !(c.margin >= 0)) bad("visibility_margin must be >= 0");
  if (!std::isfinite(c.extent_margin) || !(c.extent_margin >= 0)) bad("visibility_extent_margin must be >= 0");
  if (!std::isfinite(c.max_range) || !(c.max_range > 0)) bad("visibility_max_range must be positive");
  if (!(c.prob_hit > 0.5 && c.prob_hit < 1)) bad("prob_hit must be in (0.5, 1)");
  if (!(c.prob_miss > 0 && c.prob_miss < 0.5)) bad("prob_miss must be in (0, 0.5)");
  if (!(c.free_probability > 0 && c.free_probability < 0.5)) bad("free_probability must be in (0, 0.5)");
}

VisibilityMap::VisibilityMap(const VisibilityConfig& config) : config_(config) {
  validate(config_);
  grid_ = std::make_unique<octomap::OcTree>(config_.resolution);
}
VisibilityMap::~VisibilityMap() = default;
VisibilityMap::VisibilityMap(VisibilityMap&&) noexcept = default;
VisibilityMap& VisibilityMap::operator=(VisibilityMap&&) noexcept = default;

void VisibilityMap::add_hits(const Eigen::Matrix3Xf& points) {
  const double inv = 1.0 / config_.resolution;
  // The scan's boxes first, per kept point (no hash lookup per point), then one lookup per cell.
  const VoxelSample sample = voxel_downsample_with_owners(points, config_.resolution);
  std::vector<std::array<std::uint8_t, 6>> box(sample.keep.size(), {255, 255, 255, 0, 0, 0});
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    auto& b = box[static_cast<std::size_t>(sample.owner[static_cast<std::size_t>(i)])];
    for (int a = 0; a < 3; ++a) {
      const double f = points(a, i) * inv;
      const auto q = static_cast<std::uint8_t>(std::clamp(static_cast<int>((f - std::floor(f)) * 256.0), 0, 255));
      b[a] = std::min(b[a], q);
      b[a + 3] = std::max(b[a + 3], q);
    }
  }
  octomap::OcTreeKey k;
  for (std::size_t j = 0; j < sample.keep.size(); ++j) {
    const Eigen::Vector3f p = points.col(sample.keep[j]);
    if (!grid_->coordToKeyChecked(p.x(), p.y(), p.z(), k)) continue;  // beyond +-6.5 km
    Counts& c = cells_[voxel_of(p, inv)];
    bump(c.hits);
    for (int a = 0; a < 3; ++a) {
      c.lo[a] = std::min(c.lo[a], box[j][a]);
      c.hi[a] = std::max(c.hi[a], box[j][a + 3]);
    }
    hit_cells_.insert({k[0], k[1], k[2]});
  }
}

bool VisibilityMap::passes_hits(const CellSet::Key& k, const Eigen::Vector3d& from, const Eigen::Vector3d& dir,
                                double t0, double t1) const {
  constexpr int kOffset = 1 << 15;  // OctoMap keys are cell indices offset by 2^15
  const auto it = cells_.find(VoxelKey{k[0] - kOffset, k[1] - kOffset, k[2] - kOffset});
  if (it == cells_.end()) return false;
  const Counts& c = it->second;
  const double res = config_.resolution, step = res / 256.0;
  bool thin = false;
  for (int a = 0; a < 3; ++a) {
    if (c.lo[a] > c.hi[a]) return false;
    if ((c.hi[a] + 1 - c.lo[a]) * step >= 0.5 * res) continue;  // spread over the cell: no side to miss
    thin = true;
    const double base = (static_cast<int>(k[a]) - kOffset) * res;
    const double lo = base + c.lo[a] * step - config_.extent_margin;
    const double hi = base + (c.hi[a] + 1) * step + config_.extent_margin;
    const double za = from[a] + dir[a] * t0, zb = from[a] + dir[a] * t1;
    if (std::max(za, zb) >= lo && std::min(za, zb) <= hi) return true;  // reaches the surface's level
  }
  return !thin;
}

void VisibilityMap::add_rays(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) {
  count(cast(points, origin));
}

VisibilityMap::ScanRays VisibilityMap::cast(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) const {
  // The scan's crossed cells, each once: its rays converge on one origin, and walk_ray (from
  // the far end) stops where an earlier ray of the scan walked the rest of the way. A hit cell
  // counts as crossed once a ray reached its hits' level (passes_hits); until then it is not
  // settled, and later rays keep looking at it.
  ScanRays out;
  const auto keep = voxel_downsample(points, config_.resolution);
  octomap::OcTreeKey key;
  for (const auto i : keep) {
    if (grid_->coordToKeyChecked(points(0, i), points(1, i), points(2, i), key)) out.hit.insert({key[0], key[1], key[2]});
  }
  CellSet walked;
  CellSet::Reader ever_hit(hit_cells_);
  for (const auto i : keep) {
    const Eigen::Vector3d ray = points.col(i).cast<double>() - origin;
    const double range = ray.norm();
    if (!(range > config_.margin) || range > config_.max_range) continue;
    const Eigen::Vector3d from = origin + ray * ((range - config_.margin) / range), dir = origin - from;
    walk_ray(*grid_, from, origin, true, walked, [&](const CellSet::Key& k, double t0, double t1) {
      if (!ever_hit.contains(k) || out.crossed.contains(k)) return true;
      if (!passes_hits(k, from, dir, t0, t1)) return false;
      out.crossed.insert(k);
      return true;
    });
  }
  return out;
}

void VisibilityMap::count(const ScanRays& rays) {
  // OctoMap keys are cell indices offset by 2^15.
  constexpr int kOffset = 1 << 15;
  // Only cells hit at some time are counted (AND of the bitmaps, tile by tile). A cell the
  // scan both hits and crosses says nothing about motion: porous (foliage lets some rays
  // through) or grazed (a wall seen at a shallow angle). A mover is opaque: the scans that see
  // through its cells do not hit them.
  rays.crossed.for_each_also_in(hit_cells_, rays.hit, [&](const CellSet::Key& k) {
    const auto it = cells_.find(VoxelKey{k[0] - kOffset, k[1] - kOffset, k[2] - kOffset});
    if (it != cells_.end()) bump(it.value().crossed);
  });
}

VisibilityMap::Counts VisibilityMap::counts(const Eigen::Vector3f& p) const {
  const auto it = cells_.find(voxel_of(p, 1.0 / config_.resolution));
  return it == cells_.end() ? Counts{} : it->second;
}

std::vector<std::uint8_t> VisibilityMap::moved_through(const Eigen::Matrix3Xf& points) const {
  auto logit = [](double p) { return std::log(p / (1 - p)); };
  const double hit = logit(config_.prob_hit), miss = logit(config_.prob_miss), free = logit(config_.free_probability);
  auto evidence = [&](const Counts& c) { return c.hits * hit + c.crossed * miss; };
  const double inv = 1.0 / config_.resolution;
  std::vector<std::uint8_t> out(static_cast<std::size_t>(points.cols()), 0);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const VoxelKey k = voxel_of(points.col(i), inv);
    const auto own = cells_.find(k);
    if (own == cells_.end() || evidence(own->second) > free) continue;
    bool clear = true;
    for (int dx = -1; dx <= 1 && clear; ++dx) {
      for (int dy = -1; dy <= 1 && clear; ++dy) {
        for (int dz = -1; dz <= 1 && clear; ++dz) {
          const auto n = cells_.find(VoxelKey{k.x + dx, k.y + dy, k.z + dz});
          clear = n == cells_.end() || evidence(n->second) < -free;
        }
      }
    }
    out[static_cast<std::size_t>(i)] = clear;
  }
  return out;
}

}  // namespace cleanmap
