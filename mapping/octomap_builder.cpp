#include "mapping/octomap_builder.hpp"

#include <fcntl.h>
#include <octomap/OcTree.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>

#include "geometry/voxel_downsample.hpp"
#include "io/close_checked.hpp"
#include "io/error.hpp"
#include "mapping/carve_ray.hpp"
#include "mapping/cell_set.hpp"

namespace cleanmap {
namespace {

CellSet::Key key_of(const octomap::OcTreeKey& k) { return {k[0], k[1], k[2]}; }
octomap::OcTreeKey tree_key(const CellSet::Key& k) { return octomap::OcTreeKey(k[0], k[1], k[2]); }

// OctoMap's updateNode searches a cell first (to skip cells already at a clamping bound), then
// descends again to update it: that search was a third of insertion. Updating directly gives
// the same values, as the update clamps; with lazy evaluation nothing is pruned meanwhile, so
// the early exit never saved a node expansion either.
class DirectUpdateTree : public octomap::OcTree {
 public:
  using octomap::OcTree::OcTree;
  void update(const octomap::OcTreeKey& key, bool occupied) {
    bool created_root = false;
    if (root == nullptr) {
      root = new octomap::OcTreeNode();
      ++tree_size;
      created_root = true;
    }
    updateNodeRecurs(root, created_root, key, 0, occupied ? prob_hit_log : prob_miss_log, true);
  }
};

// OctoMap's writers print "Writing N nodes to output stream... done." on stderr (its
// OCTOMAP_DEBUG, compiled into Debian's library), which broke the progress lines: stderr is
// pointed at /dev/null while it writes. Nothing else prints then (the passes have finished).
class QuietStderr {
 public:
  QuietStderr() : lock_(mutex()) {
    std::fflush(stderr);
    saved_ = dup(STDERR_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
    if (null >= 0) close(null);
  }
  ~QuietStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      dup2(saved_, STDERR_FILENO);
      close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  int saved_ = -1;
};

// An OctoMap written to `file` through a stream whose state is checked: OctoMap's own file
// writers return true on a full disk (a warning on stderr, which QuietStderr hides), and the
// run reported a truncated map.ot as complete.
template <typename Write>
void write_checked(const std::filesystem::path& file, Write&& write) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) fail(file, "cannot create OctoMap file");
  bool ok = false;
  {
    QuietStderr quiet;
    ok = write(out);
  }
  if (!ok) fail(file, "write failed (disk full?)");
  close_checked(out, file);
}

}  // namespace

void validate(const MapConfig& c) {
  auto bad = [](const std::string& what) { throw Error("mapping: " + what); };
  if (!(c.resolution > 0)) bad("resolution must be positive");
  if (!(c.max_range > 0)) bad("max_range must be positive");
  if (!(c.prob_hit > 0.5 && c.prob_hit < 1)) bad("prob_hit must be in (0.5, 1)");
  if (!(c.prob_miss > 0 && c.prob_miss < 0.5)) bad("prob_miss must be in (0, 0.5)");
  if (!(c.clamp_min > 0 && c.clamp_min < c.clamp_max && c.clamp_max < 1)) {
    bad("need 0 < clamp_min < clamp_max < 1");
  }
  if (c.insert_voxel < 0) bad("insert_voxel must be >= 0");
  // OctoMap's keys are 16-bit: a tree reaches 32768 leaves from its origin, and rays beyond that
  // fail one error line per point (a 1e-9 m resolution printed 19k of them).
  if (c.max_range / c.resolution > kMaxCellsPerRay) {
    char msg[200];
    std::snprintf(msg, sizeof msg, "resolution %g m is too fine for map_max_range %g m: a ray would walk %.0f cells "
                  "(at most %.0f)", c.resolution, c.max_range, c.max_range / c.resolution, kMaxCellsPerRay);
    bad(msg);
  }
  if (c.resolution * 32768.0 < c.max_range) {
    char msg[200];
    std::snprintf(msg, sizeof msg, "resolution %g m is too fine for map_max_range %g m (OctoMap's 16-bit keys reach "
                  "32768 leaves from the origin)", c.resolution, c.max_range);
    bad(msg);
  }
}

OctoMapBuilder::OctoMapBuilder(const MapConfig& config)
    : config_(config), tree_(std::make_unique<DirectUpdateTree>(config.resolution)) {
  validate(config_);
  tree_->setProbHit(config.prob_hit);
  tree_->setProbMiss(config.prob_miss);
  tree_->setClampingThresMin(config.clamp_min);
  tree_->setClampingThresMax(config.clamp_max);
}

OctoMapBuilder::~OctoMapBuilder() = default;

namespace {

// Where the sensor was when it fired point i: `times` one per point (else all from the start).
struct RayOrigins {
  const Eigen::VectorXf& times;
  const SweepOrigin& sensor;
  bool timed;
  RayOrigins(const Eigen::VectorXf& t, const SweepOrigin& s, Eigen::Index points)
      : times(t), sensor(s), timed(t.size() == points && s.velocity != Eigen::Vector3d::Zero()) {}
  Eigen::Vector3d operator()(Eigen::Index i) const {
    return timed && std::isfinite(times[i]) ? sensor.at(times[i]) : sensor.start;
  }
};

// The cells of `points` within `max_range` of where the sensor was when it fired each one:
// what insert marks occupied and pin keeps. Returns how many of them lie beyond the tree's
// 16-bit keys (they are left out).
std::size_t add_hit_cells(const octomap::OcTree& tree, double max_range, const Eigen::Matrix3Xf& points,
                          const RayOrigins& origin_of, CellSet& cells) {
  const double max_sq = max_range * max_range;
  std::size_t beyond = 0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if ((points.col(i).cast<double>() - origin_of(i)).squaredNorm() > max_sq) continue;
    octomap::OcTreeKey key;
    if (tree.coordToKeyChecked(points(0, i), points(1, i), points(2, i), key)) {
      cells.insert(key_of(key));
    } else {
      ++beyond;
    }
  }
  return beyond;
}

}  // namespace

void OctoMapBuilder::insert(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) {
  insert(points, Eigen::VectorXf(), SweepOrigin{origin});
}

void OctoMapBuilder::insert(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times,
                            const SweepOrigin& sensor) {
  const RayOrigins origin_of(times, sensor, points.cols());
  // Occupied cells from every point (one update per cell); free space carved by rays to a
  // sparser subsample only: rays are the cost, and neighbouring rays cross the same cells.
  CellSet occupied;
  beyond_reach_ += add_hit_cells(*tree_, config_.max_range, points, origin_of, occupied);
  const double voxel = config_.insert_voxel > 0 ? config_.insert_voxel : config_.resolution;
  auto rays = voxel_downsample(points, voxel);
  // In firing order: carve_ray stops where earlier rays carved on, which holds for rays from
  // about the same origin (at 5 m/s the sensor moves 5 cm while it turns 36 degrees).
  if (origin_of.timed) {
    std::stable_sort(rays.begin(), rays.end(), [&](auto a, auto b) { return times[a] < times[b]; });
  }
  CellSet carved;
  for (const auto i : rays) {
    const Eigen::Vector3d p = points.col(i).cast<double>(), origin = origin_of(i);
    const double length = (p - origin).norm();
    // A ray longer than the range limit is cut and carves free space up to the cut; its end
    // cell is not a hit.
    if (length > config_.max_range) {
      carve_ray(*tree_, origin + (p - origin) * (config_.max_range / length), origin, true, carved);
    } else {
      carve_ray(*tree_, p, origin, false, carved);
    }
  }
  auto& tree = static_cast<DirectUpdateTree&>(*tree_);
  carved.for_each_in_tree_order([&](const CellSet::Key& k) {
    if (!occupied.contains(k)) tree.update(tree_key(k), false);
  });
  occupied.for_each_in_tree_order([&](const CellSet::Key& k) { tree.update(tree_key(k), true); });
}

void OctoMapBuilder::pin(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times,
                         const SweepOrigin& sensor) {
  if (!pinned_) pinned_ = std::make_unique<CellSet>();
  add_hit_cells(*tree_, config_.max_range, points, RayOrigins(times, sensor, points.cols()),
                *pinned_);
}

std::size_t OctoMapBuilder::occupy_pinned() {
  if (!pinned_) return 0;
  const float hit = octomap::logodds(config_.prob_hit);
  std::size_t turned = 0;
  pinned_->for_each_in_tree_order([&](const CellSet::Key& k) {
    const auto* node = tree_->search(tree_key(k));
    if (node && node->getLogOdds() >= hit) return;
    tree_->setNodeValue(tree_key(k), hit, true);
    ++turned;
  });
  return turned;
}

std::vector<std::uint8_t> OctoMapBuilder::hits_in_free_space(const Eigen::Matrix3Xf& points) const {
  std::vector<std::uint8_t> hit(static_cast<std::size_t>(points.cols()), 0);
  const double free_logodds = octomap::logodds(config_.free_probability);
  const double res = config_.resolution;
  // Read-only searches: safe in parallel.
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, points.cols(), 1024), [&](const auto& r) {
  for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
    // Keys checked first: OctoMap's search prints an error line per point beyond its reach.
    octomap::OcTreeKey key;
    if (!tree_->coordToKeyChecked(points(0, i), points(1, i), points(2, i), key)) continue;
    const auto* node = tree_->search(key);
    if (!node || node->getLogOdds() > free_logodds) continue;
    // Rays grazing a static surface carve the cells it lies in; a real intruder sits in free
    // space, with no occupied cell around it.
    bool clear = true;
    for (int dx = -1; dx <= 1 && clear; ++dx) {
      for (int dy = -1; dy <= 1 && clear; ++dy) {
        for (int dz = -1; dz <= 1 && clear; ++dz) {
          octomap::OcTreeKey near;
          if (!tree_->coordToKeyChecked(points(0, i) + dx * res, points(1, i) + dy * res, points(2, i) + dz * res, near)) continue;
          const auto* n = tree_->search(near);
          clear = !(n && tree_->isNodeOccupied(n));
        }
      }
    }
    hit[static_cast<std::size_t>(i)] = clear;
  }
  });
  return hit;
}

void OctoMapBuilder::write_binary(const std::filesystem::path& file) {
  tree_->updateInnerOccupancy();
  // A .bt keeps only free / occupied: children that differ in log-odds but not in that state
  // merge losslessly, so the copy written is the maximum-likelihood tree pruned (162,709 B ->
  // 118,161 B on the demo, what OctoMap's own read-prune-write gave). A copy, because
  // OcTree::writeBinary turns the map itself into maximum likelihood and a .ot written
  // afterwards lost its probabilities.
  octomap::OcTree binary(*tree_);
  binary.toMaxLikelihood();
  binary.prune();
  write_checked(file, [&](std::ostream& out) { return binary.writeBinaryConst(out); });
}

void OctoMapBuilder::write_full(const std::filesystem::path& file) {
  tree_->updateInnerOccupancy();
  tree_->prune();  // lossless: merges only children with equal log-odds (the clamped ones)
  write_checked(file, [&](std::ostream& out) { return tree_->write(out); });
}

namespace {

// The ground under each grid column: its own lowest occupied cell when that lies within
// kGroundStep of the lowest one within kGroundReach (a road, a wall's or a box's footing: exact
// on slopes), else that lowest one nearby (under a car's body or a tree's canopy the column's
// own lowest cell is no ground). Columns with nothing within reach take the map's lowest.
std::vector<double> local_ground(const octomap::OcTree& tree, double x0, double y0, double res, int w, int h) {
  constexpr double kGroundReach = 2.0;  // m: half a car's width, a wall's footing to the road
  constexpr double kGroundStep = 0.5;   // m: a curb, 6% over the reach, a cell of quantization
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> low(static_cast<std::size_t>(w) * h, inf);
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const double half = it.getSize() / 2, z = it.getZ() - half + res / 2;  // its lowest cell's centre
    for (double x = it.getX() - half + res / 2; x < it.getX() + half; x += res) {
      for (double y = it.getY() - half + res / 2; y < it.getY() + half; y += res) {
        const int cx = static_cast<int>((x - x0) / res), cy = static_cast<int>((y - y0) / res);
        if (cx < 0 || cy < 0 || cx >= w || cy >= h) continue;
        double& v = low[static_cast<std::size_t>(cy) * w + cx];
        v = std::min(v, z);
      }
    }
  }
  const int r = static_cast<int>(std::ceil(kGroundReach / res));
  std::vector<double> rows(low.size(), inf), out(low.size(), inf);
  for (int cy = 0; cy < h; ++cy) {
    for (int cx = 0; cx < w; ++cx) {
      double m = inf;
      for (int k = std::max(0, cx - r); k <= std::min(w - 1, cx + r); ++k) m = std::min(m, low[static_cast<std::size_t>(cy) * w + k]);
      rows[static_cast<std::size_t>(cy) * w + cx] = m;
    }
  }
  double lowest = inf;
  for (double v : low) lowest = std::min(lowest, v);
  for (int cy = 0; cy < h; ++cy) {
    for (int cx = 0; cx < w; ++cx) {
      double m = inf;
      for (int k = std::max(0, cy - r); k <= std::min(h - 1, cy + r); ++k) m = std::min(m, rows[static_cast<std::size_t>(k) * w + cx]);
      const double own = low[static_cast<std::size_t>(cy) * w + cx];
      out[static_cast<std::size_t>(cy) * w + cx] = !std::isfinite(m) ? lowest : own <= m + kGroundStep ? own : m;
    }
  }
  return out;
}

}  // namespace

void OctoMapBuilder::write_occupancy_grid(const std::filesystem::path& pgm, double z_min,
                                          double z_max) {
  tree_->updateInnerOccupancy();
  double x0, y0, z0, x1, y1, z1;
  tree_->getMetricMin(x0, y0, z0);
  tree_->getMetricMax(x1, y1, z1);
  const double res = config_.resolution;
  const int w = std::max(1, static_cast<int>(std::ceil((x1 - x0) / res)));
  const int h = std::max(1, static_cast<int>(std::ceil((y1 - y0) / res)));
  // The band [z_min, z_max] is height above the local ground, not world z: world z starts at
  // the first sensor pose, and on a car the default 0.3-2.0 m band lay 2.3-4 m above the road.
  const std::vector<double> ground = local_ground(*tree_, x0, y0, res, w, h);
  // map_server: 0 = occupied (black), 254 = free (white), 205 = unknown.
  std::vector<std::uint8_t> grid(static_cast<std::size_t>(w) * h, 205);
  for (auto it = tree_->begin_leafs(); it != tree_->end_leafs(); ++it) {
    const double half = it.getSize() / 2;
    const bool occupied = tree_->isNodeOccupied(*it);
    for (double x = it.getX() - half + res / 2; x < it.getX() + half; x += res) {
      for (double y = it.getY() - half + res / 2; y < it.getY() + half; y += res) {
        const int cx = static_cast<int>((x - x0) / res), cy = static_cast<int>((y - y0) / res);
        if (cx < 0 || cy < 0 || cx >= w || cy >= h) continue;
        const double above = it.getZ() - ground[static_cast<std::size_t>(cy) * w + cx];
        if (above < z_min || above > z_max) continue;
        auto& cell = grid[static_cast<std::size_t>(h - 1 - cy) * w + cx];  // image rows go down
        if (occupied) cell = 0;
        else if (cell == 205) cell = 254;
      }
    }
  }
  {
    std::ofstream out(pgm, std::ios::binary);
    if (!out) fail(pgm, "cannot create file");
    out << "P5\n" << w << ' ' << h << "\n255\n";
    out.write(reinterpret_cast<const char*>(grid.data()), static_cast<std::streamsize>(grid.size()));
    close_checked(out, pgm);
  }
  auto yaml = pgm;
  yaml.replace_extension(".yaml");
  std::ofstream meta(yaml);
  if (!meta) fail(yaml, "cannot create file");
  meta << "image: " << pgm.filename().string() << "\nresolution: " << res << "\norigin: [" << x0
       << ", " << y0 << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  close_checked(meta, yaml);
}

std::size_t OctoMapBuilder::leaf_count() const { return tree_->getNumLeafNodes(); }

}  // namespace cleanmap
