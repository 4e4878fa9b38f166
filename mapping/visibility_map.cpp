#include "mapping/visibility_map.hpp"

#include <octomap/OcTree.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/error.hpp"
#include "geometry/voxel_downsample.hpp"
#include "mapping/carve_ray.hpp"

namespace cleanmap {
namespace {

constexpr std::uint16_t kMaxCount = std::numeric_limits<std::uint16_t>::max();

void bump(std::uint16_t& c) { c = static_cast<std::uint16_t>(std::min<int>(c + 1, kMaxCount)); }

using Counts = VisibilityMap::Counts;

// Two cells' hits are at one level when they are this close (m): range noise (1-2 cm) and the
// pose error between scans (2-3 cm), as extent_margin.
constexpr double kLevelTolerance = 0.05;

// Thin along `a`: the hits fill under half the cell there (a surface's side can be missed).
bool thin(const Counts& c, int a) { return c.lo[a] <= c.hi[a] && c.hi[a] + 1 - c.lo[a] < 128; }
int thin_axes(const Counts& c) { return thin(c, 0) + thin(c, 1) + thin(c, 2); }

// Where the hits of a cell lie along axis `a` (m): `cell` is its index along that axis.
std::pair<double, double> hits_level(int cell, const Counts& c, int a, double res) {
  const double step = res / 256.0;
  return {cell * res + c.lo[a] * step, cell * res + (c.hi[a] + 1) * step};
}

}  // namespace

// The axes a cell's hits face along (bit a), when they are a line or a dot (thin along two axes
// or three): the thin axes along which neighbouring cells hold hits at the same level (within
// kLevelTolerance) in two directions across it that are not one line (a roof's other rings, a
// side's rows above and below). Two bits: an edge (a roof meeting a side). 0: a line alone, or
// nothing around it to tell. Only neighbours in the 3x3x3 block are read.
std::uint8_t VisibilityMap::faces(const VoxelKey& k, const Counts& c) const {
  if (thin_axes(c) < 2) return 0;
  const double res = config_.resolution;
  auto level = [&](const VoxelKey& m, const Counts& n, int a) {
    return hits_level(a == 0 ? m.x : a == 1 ? m.y : m.z, n, a, res);
  };
  std::array<int, 3> found{0, 0, 0};  // per axis: 0 none, 1 one direction (or a line), 2 a plane
  std::array<std::array<int, 2>, 3> first{};  // the first supporting direction, per axis
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        const VoxelKey m{k.x + dx, k.y + dy, k.z + dz};
        const auto it = cells_.find(m);
        if ((dx == 0 && dy == 0 && dz == 0) || it == cells_.end()) continue;
        const std::array<int, 3> d{dx, dy, dz};
        for (int a = 0; a < 3; ++a) {
          if (!thin(c, a) || !thin(it->second, a) || found[a] == 2) continue;
          const std::array<int, 2> across{d[(a + 1) % 3], d[(a + 2) % 3]};
          if (across[0] == 0 && across[1] == 0) continue;  // straight above or below: not beside it
          const auto own = level(k, c, a), other = level(m, it->second, a);
          if (other.first > own.second + kLevelTolerance || other.second < own.first - kLevelTolerance) continue;
          if (found[a] == 0) {
            first[a] = across;
            found[a] = 1;
          } else if (first[a][0] * across[1] != first[a][1] * across[0]) {
            found[a] = 2;
          }
        }
      }
    }
  }
  std::uint8_t faces = 0;
  for (int a = 0; a < 3; ++a) faces |= found[a] == 2 ? 1 << a : 0;
  return faces;
}

void VisibilityMap::fit_surfaces() {
  std::vector<std::pair<VoxelKey, Counts*>> lines;
  for (auto it = cells_.begin(); it != cells_.end(); ++it) {
    if (thin_axes(it->second) >= 2) lines.emplace_back(it->first, &it.value());
  }
  // Read the map side by side, write once all are read (a neighbour's box is never changed).
  std::vector<std::uint8_t> fitted(lines.size());
  tbb::parallel_for(std::size_t{0}, lines.size(),
                    [&](std::size_t i) { fitted[i] = faces(lines[i].first, *lines[i].second); });
  for (std::size_t i = 0; i < lines.size(); ++i) lines[i].second->faces = fitted[i];
  surfaces_fitted_ = true;
}

void validate(const VisibilityConfig& c) {
  auto bad = [](const std::string& what) { throw Error("visibility: " + what); };
  if (!std::isfinite(c.resolution) || !(c.resolution > 0)) bad("visibility_resolution must be positive");
  if (c.max_range / c.resolution > kMaxCellsPerRay) {
    bad("visibility_resolution is too fine for visibility_max_range: a ray would walk over 10000 cells");
  }
  if (!std::isfinite(c.margin) || !(c.margin >= 0)) bad("visibility_margin must be >= 0");
  if (!std::isfinite(c.extent_margin) || !(c.extent_margin >= 0)) bad("visibility_extent_margin must be >= 0");
  if (!std::isfinite(c.angular_margin) || !(c.angular_margin >= 0))
    bad("visibility_angular_margin must be >= 0");
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

void VisibilityMap::add_hits(const Eigen::Matrix3Xf& points, const std::optional<Eigen::Vector3d>& origin) {
  add_hits(hits_of(points, origin));
}

VisibilityMap::ScanHits VisibilityMap::hits_of(const Eigen::Matrix3Xf& points,
                                               const std::optional<Eigen::Vector3d>& origin) const {
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
  ScanHits out;
  out.cells.reserve(sample.keep.size());
  octomap::OcTreeKey k;
  for (std::size_t j = 0; j < sample.keep.size(); ++j) {
    const Eigen::Vector3f p = points.col(sample.keep[j]);
    if (!grid_->coordToKeyChecked(p.x(), p.y(), p.z(), k)) continue;  // beyond +-6.5 km
    std::uint8_t seen_from = 0;
    if (origin) {
      for (int a = 0; a < 3; ++a) seen_from |= p[a] > (*origin)[a] ? 1 << a : 1 << (a + 3);
    }
    out.cells.push_back({voxel_of(p, inv), {k[0], k[1], k[2]}, box[j], seen_from});
  }
  return out;
}

void VisibilityMap::add_hits(const ScanHits& hits) {
  for (const ScanHits::Cell& h : hits.cells) {
    Counts& c = cells_[h.cell];
    bump(c.hits);
    c.first_hit = std::min(c.first_hit, hit_scans_);
    c.last_hit = std::max(c.last_hit, hit_scans_);
    c.seen_from |= h.seen_from;
    for (int a = 0; a < 3; ++a) {
      c.lo[a] = std::min(c.lo[a], h.box[a]);
      c.hi[a] = std::max(c.hi[a], h.box[a + 3]);
    }
    hit_cells_.insert(h.key);
  }
  if (hit_scans_ < kLastScan) ++hit_scans_;
  surfaces_fitted_ = false;
}

namespace {

// Narrows [ta, tb] to where the segment from + dir t has coordinate `a` in [lo, hi] (tb < ta:
// nowhere).
void clip(const Eigen::Vector3d& from, const Eigen::Vector3d& dir, int a, double lo, double hi, double& ta,
          double& tb) {
  if (dir[a] == 0) {
    if (from[a] < lo || from[a] > hi) tb = ta - 1;
    return;
  }
  const double u = (lo - from[a]) / dir[a], v = (hi - from[a]) / dir[a];
  ta = std::max(ta, std::min(u, v));
  tb = std::min(tb, std::max(u, v));
}

// A scan's rays cut by time into spans the sensor crosses in VisibilityMap::kOriginStep
// (`speed` m/s): members[s] holds the points of span s, which starts at t0 + s * step. One span
// without times or motion. At most kMaxSpans (a sweep of 0.1 s at 50 m/s).
struct SweepSpans {
  double t0 = 0.0, step = 0.0;
  std::vector<std::vector<std::int32_t>> members;
};
constexpr int kMaxSpans = 256;
SweepSpans sweep_spans(const std::vector<std::int32_t>& keep, const Eigen::VectorXf& times, double speed) {
  SweepSpans out;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const bool timed = times.size() > 0 && std::isfinite(speed) && speed > 0;
  if (timed) {
    for (const auto i : keep) {
      lo = std::min(lo, static_cast<double>(times[i]));
      hi = std::max(hi, static_cast<double>(times[i]));
    }
  }
  const double travel = speed * (hi - lo);
  const int n = timed && std::isfinite(travel) && travel > VisibilityMap::kOriginStep
                    ? static_cast<int>(std::min<double>(kMaxSpans, std::ceil(travel / VisibilityMap::kOriginStep)))
                    : 1;
  const bool spread = timed && std::isfinite(lo) && std::isfinite(hi);
  out.t0 = spread ? lo : 0.0;  // one span: from the middle of its times (the stamp without)
  out.step = spread ? (hi - lo) / n : 0.0;
  out.members.resize(static_cast<std::size_t>(n));
  for (const auto i : keep) {
    const double t = n > 1 ? (times[i] - lo) / out.step : 0.0;  // NaN time: the first span
    const int s = std::isfinite(t) ? std::clamp(static_cast<int>(std::min<double>(t, n)), 0, n - 1) : 0;
    out.members[static_cast<std::size_t>(s)].push_back(i);
  }
  return out;
}

}  // namespace

VisibilityMap::Crossing VisibilityMap::crossing(const CellSet::Key& k, const Eigen::Vector3d& from,
                                                const Eigen::Vector3d& dir, double t0, double t1) const {
  constexpr int kOffset = 1 << 15;  // OctoMap keys are cell indices offset by 2^15
  const auto it = cells_.find(VoxelKey{k[0] - kOffset, k[1] - kOffset, k[2] - kOffset});
  if (it == cells_.end()) return Crossing::kNone;
  const Counts& c = it->second;
  const double margin = config_.extent_margin, inf = std::numeric_limits<double>::infinity();
  std::array<std::pair<double, double>, 3> level;
  for (int a = 0; a < 3; ++a) {
    if (c.lo[a] > c.hi[a]) return Crossing::kNone;
    level[a] = hits_level(static_cast<int>(k[a]) - kOffset, c, a, config_.resolution);
    // Where the hits spread over the cell, a ray beside them (the empty part of the cell, above
    // a car's roof in the cell of its side's top row) does not cross them either.
    const double za = from[a] + dir[a] * t0, zb = from[a] + dir[a] * t1;
    if (!thin(c, a) && (std::max(za, zb) < level[a].first - margin || std::min(za, zb) > level[a].second + margin)) {
      return Crossing::kNone;
    }
  }
  // The band along `a` a ray must reach, grown by `grow`: hit from one side only, beyond the
  // level is inside what was hit, and passing there crosses it (a ray under a roof's level
  // goes through the car beneath it). `inside`: shrunk by that much on that side.
  auto band = [&](int a, double grow, double inside = 0.0) {
    const bool from_low = c.seen_from >> a & 1, from_high = c.seen_from >> (a + 3) & 1;
    const double lo = level[a].first - grow, hi = level[a].second + grow;
    if (from_low && !from_high) return std::pair{lo + inside, inf};
    if (from_high && !from_low) return std::pair{-inf, hi - inside};
    return std::pair{lo, hi};
  };
  // Through, where the hits were seen from one side: beyond their level by the beam's width
  // and the pose's rotation error at this range (t = 0 at `from`, 1 at the sensor). A level
  // seen from both sides (or none known) has no inside to pass into: reaching it counts.
  const double beyond = config_.angular_margin * (1.0 - std::min(t0, t1)) * dir.norm();
  auto reaches = [&](int a) {
    double ta = t0, tb = t1;
    const auto near = band(a, margin);
    clip(from, dir, a, near.first, near.second, ta, tb);
    if (tb < ta) return Crossing::kNone;
    ta = t0, tb = t1;
    const auto at = band(a, 0.0, beyond);
    clip(from, dir, a, at.first, at.second, ta, tb);
    return tb < ta ? Crossing::kNear : Crossing::kThrough;
  };
  if (c.faces != 0) {  // an edge (two faces) is crossed only where the ray reaches both
    auto out = Crossing::kThrough;
    for (int a = 0; a < 3; ++a) {
      if (c.faces >> a & 1) out = std::min(out, reaches(a));
    }
    if (out != Crossing::kThrough) return out;
    // Through a face's level beside its hits (past a roof's edge) is near it, not through it.
    double ta = t0, tb = t1;
    for (int a = 0; a < 3; ++a) {
      const auto b = c.faces >> a & 1
                         ? band(a, 0.0, beyond)
                         : std::pair{level[a].first - margin, level[a].second + margin};
      clip(from, dir, a, b.first, b.second, ta, tb);
    }
    return tb < ta ? Crossing::kNear : Crossing::kThrough;
  }
  if (thin_axes(c) == 3) {  // a dot: through it only inside its hits along every axis
    const std::array<Crossing, 3> r{reaches(0), reaches(1), reaches(2)};
    const auto [lowest, highest] = std::minmax_element(r.begin(), r.end());
    if (*highest == Crossing::kNone) return Crossing::kNone;
    return *lowest == Crossing::kThrough ? Crossing::kThrough : Crossing::kNear;
  }
  auto out = Crossing::kNone;
  bool any_thin = false;
  for (int a = 0; a < 3; ++a) {
    if (!thin(c, a)) continue;  // spread over the cell: no side to miss
    any_thin = true;
    out = std::max(out, reaches(a));
  }
  return any_thin ? out : Crossing::kThrough;
}

void VisibilityMap::add_rays(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) {
  if (!surfaces_fitted_) fit_surfaces();
  count(cast(points, origin));
}

VisibilityMap::ScanRays VisibilityMap::cast(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) const {
  return cast(points, Eigen::VectorXf(), SweepOrigin{origin});
}

VisibilityMap::ScanRays VisibilityMap::cast(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times,
                                            const SweepOrigin& sensor) const {
  if (!surfaces_fitted_) throw std::logic_error("VisibilityMap::cast before fit_surfaces");
  ScanRays out;
  const auto keep = voxel_downsample(points, config_.resolution);
  octomap::OcTreeKey key;
  for (const auto i : keep) {
    if (grid_->coordToKeyChecked(points(0, i), points(1, i), points(2, i), key)) out.hit.insert({key[0], key[1], key[2]});
  }
  // The scan's crossed cells, each once: a span's rays converge on one origin, and walk_ray
  // (from the far end) stops where an earlier ray of the span walked the rest of the way. A hit
  // cell counts as crossed once a ray came near its hits (crossing), and is settled once one
  // went through them; until then later rays keep looking at it.
  const bool timed = times.size() == points.cols();  // otherwise every ray from the stamp's origin
  const auto spans = sweep_spans(keep, timed ? times : Eigen::VectorXf(), sensor.velocity.norm());
  CellSet::Reader ever_hit(hit_cells_);
  for (std::size_t s = 0; s < spans.members.size(); ++s) {
    if (spans.members[s].empty()) continue;
    const Eigen::Vector3d origin = sensor.at(spans.t0 + (static_cast<double>(s) + 0.5) * spans.step);
    CellSet walked;  // a span's rays share its origin: walk_ray stops where another walked on
    cast_span(points, spans.members[s], origin, walked, ever_hit, out);
  }
  return out;
}

void VisibilityMap::cast_span(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& span,
                              const Eigen::Vector3d& origin, CellSet& walked, CellSet::Reader& ever_hit,
                              ScanRays& out) const {
  for (const auto i : span) {
    const Eigen::Vector3d ray = points.col(i).cast<double>() - origin;
    const double range = ray.norm();
    if (!(range > config_.margin) || range > config_.max_range) continue;
    const Eigen::Vector3d from = origin + ray * ((range - config_.margin) / range), dir = origin - from;
    walk_ray(*grid_, from, origin, true, walked, [&](const CellSet::Key& k, double t0, double t1) {
      if (!ever_hit.contains(k) || out.through.contains(k)) return true;
      const Crossing how = crossing(k, from, dir, t0, t1);
      if (how == Crossing::kNone) return false;
      out.crossed.insert(k);
      if (how == Crossing::kNear) return false;  // unsettled: a later ray may go through it
      out.through.insert(k);
      return true;
    });
  }
}

void VisibilityMap::count(const ScanRays& rays) {
  // This call's rays are scan ray_scans_'s: that scan's hits must be in (add_hits numbers them).
  if (ray_scans_ >= hit_scans_ && hit_scans_ < kLastScan) {
    throw std::logic_error("VisibilityMap::count: more scans' rays than scans' hits");
  }
  // OctoMap keys are cell indices offset by 2^15.
  constexpr int kOffset = 1 << 15;
  // Only cells hit at some time are counted (AND of the bitmaps, tile by tile). A cell the
  // scan both hits and crosses says nothing about motion: porous (foliage lets some rays
  // through) or grazed (a wall seen at a shallow angle). A mover is opaque: the scans that see
  // through its cells do not hit them.
  // The cells gone through are among those crossed (cast): one look-up of the counts each.
  CellSet::Reader through(rays.through);
  rays.crossed.for_each_also_in(hit_cells_, rays.hit, [&](const CellSet::Key& k) {
    const auto it = cells_.find(VoxelKey{k[0] - kOffset, k[1] - kOffset, k[2] - kOffset});
    if (it == cells_.end()) return;
    bump(it.value().crossed);
    if (!through.contains(k)) return;
    Counts& c = it.value();
    bump(c.through);
    if (ray_scans_ < c.first_hit || ray_scans_ > c.last_hit) bump(c.through_apart);
  });
  if (ray_scans_ < kLastScan) ++ray_scans_;
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
    // A cell only ever crossed near its hits may be a surface the rays grazed.
    if (own == cells_.end() || own->second.through == 0) continue;
    if (evidence(own->second) > free && !own->second.left()) continue;
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
