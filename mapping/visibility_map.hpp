#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"
#include "mapping/cell_set.hpp"
#include "mapping/sweep_origin.hpp"

namespace octomap {
class OcTree;
}

namespace cleanmap {

// What the whole log saw in each occupied cell: in how many scans something was hit there, in
// how many a ray crossed it on its way to a hit farther on. A cell crossed in more scans than
// it was hit held something only part of the time: it moved. DUFOMap (Duberg et al., RA-L
// 2024) calls a cell crossed by any ray at any time "void"; on the Pandar64 street (scans
// 0.6 m apart, not deskewed) that removed 41% of the static world here, as the benchmark
// measured for DUFOMap itself (SA 59 against 63): rays graze walls and the ground in some
// scans, and those cells are hit in many more.
// A ray stops `margin` short of its hit, so that what blurs a surface in depth never counts
// as crossing it: range noise (3 sigma of 1-2 cm), pose error (2-5 cm), the cell's half
// diagonal (0.17 m at 0.2 m: a hit near a cell's far corner must not cross that cell), and
// deskew residue where scans are not deskewed (up to speed x sweep time). 0.3 m by default.
// Rays longer than `max_range` are not cast: a beam's footprint grows with range (3 mrad:
// 0.3 m at 100 m) and no longer fits a cell.
// A cell is coarse next to what it holds: a car's roof at 1.5 m fills the bottom of its
// [1.4, 1.6) cell, and rays that pass over the roof to the ground behind cross the cell's top
// in every scan that does not hit the roof (on the static synthetic street, 517 of its 912
// false points). So each cell keeps the box its hits filled over the whole log, and along an
// axis where that box is thin (under half a cell: the roof's z, a wall's normal) a ray counts
// as crossing the cell only where it reaches the hits' level, within `extent_margin`: what
// blurs a ray against another scan's hits (pose error between scans, a few cm; range noise is
// in the box already, as every hit of every scan is). A ray that reaches the level of a thin
// axis counts, whatever the others: the hits of a far car are a row or two, thin along z as
// well as along its side's normal, and rays between the rows still pass through its side.
// Boxes against whole cells, bench/quality.sh: synthetic street 0.948 -> 0.951, SemanticKITTI
// 01 0.649 -> 0.651, Pandar64 0.450 -> 0.454 (SA 94.61 -> 94.70), the rest unchanged.
// Requiring the whole box instead (every axis) lost recall on the sparse hits of movers
// (SemanticKITTI 01 0.618, synthetic 0.940).
// A box thin along two axes is a line of hits (one ring across a roof, one row of a car's
// side): from the cell alone a ray 5 cm over a roof and one between two rows of a side are the
// same. Its neighbours tell them apart: where cells beside it hold hits at its level along one
// thin axis, in two directions (a roof's other rings, a side's rows above and below), that is
// the axis its hits face, and only that axis counts; at an edge (two such axes) the ray must
// reach both (fit_surfaces). And a cell hit from one side only (the sensor above a roof) is
// crossed by a ray that passes beyond its level, inside what was hit (under a roof's level,
// through the car beneath it), as well as by one that reaches it.
// Against the boxes alone, bench/quality.sh: SemanticKITTI 01 0.651 -> 0.668 (precision 0.870
// -> 0.922), 07 0.956 -> 0.974, KITTI 00 0.487 -> 0.495, 04 0.896 -> 0.895, Pandar64 0.530 ->
// 0.531, synthetic street 0.952 either way; the static synthetic log 268 -> 213 false points.
// Faces without the inside rule lost the synthetic street's movers (0.948): rays under a far
// car's roof cross its body, not its roof's level.
// Near and through. A ray within extent_margin of a cell's hits may only graze a surface: on
// the static synthetic log, the rings over parked cars' roofs 0.3 m below the sensor pass 3-5 cm
// over them, for metres at 48 m. Such a crossing still weighs the cell (`crossed`), but only a
// ray through the hits themselves, with no margin (through their level, or beyond it inside
// what was hit: `through`), shows that what stood there left. So a cell is moved through only
// if one ray went through it, and inside the log the normals' call stands only on an object one
// went through (whole_log_vote). Through means, besides the level:
// - along a face, crossing its level inside the hits' box along the other axes (grown by the
//   margin): a ray that meets a roof's level past its edge went by the roof;
// - for a dot (a lone hit, thin along every axis, nothing around it to tell its faces): inside
//   its hits along every axis. Requiring that even to count as crossed (a ray 3 cm over a far
//   car's single hit beside it) cost SemanticKITTI 01 0.668 -> 0.650.
// And along an axis where the hits spread over the cell, a ray beyond their box (grown by the
// margin) does not cross them at all: the empty top of the cell holding a car's roof corner.
// bench/quality.sh, before -> after: the static synthetic log 52 -> 0 false points with
// odometry (213 -> 42 on given poses), SemanticKITTI 01 0.668 -> 0.672, 04 0.895 -> 0.899, 07
// 0.974 -> 0.980, KITTI 00 0.495 -> 0.534, Pandar64 0.558 -> 0.561 (SA 94.78 -> 94.88),
// synthetic street 0.957 -> 0.954.
// A beam, not a line. A beam is a cone (the VLS-128's spreads 1.5 mrad vertically, 3 mrad
// horizontally: its manual, table F-1) and a pose is off in rotation as well, so a ray's
// centre line can pass a hit's level by less than `angular_margin` times its range and still
// only have grazed it: with our odometry's poses, rings passing over parked cars' roofs 0.2 m
// under the sensor, 48 m away, dipped under the roofs' level. Where the hits were seen from
// one side, through asks a ray to pass that far beyond their level, inside what was hit
// (seen from both sides, a level has no inside: reaching it counts, as before). 1 mrad (half
// the beam's spread plus a pose's rotation error) against none, bench/quality.sh:
// SemanticKITTI 07 0.985 -> 0.992, kitti00 0.542 -> 0.638 (a static patch 65 m away that the
// normals call moving: its cells no longer gone through, it is static in scans 1 and 2),
// Pandar64 0.574 -> 0.576, 04 0.928 either way, 01 0.671 -> 0.657, synthetic street 0.954 ->
// 0.953. With moved_through's rule below, 1.5 and 3 mrad took 01 from 0.721 (1 mrad) to 0.712
// and 0.632 (measured with a first version that also narrowed levels seen from both sides; at
// 1 mrad it gave the same tables).
struct VisibilityConfig {
  double resolution = 0.2;  // m
  double margin = 0.3;      // m
  double extent_margin = 0.05;  // m; a resolution or more: whole cells, as without boxes
  double angular_margin = 0.001;  // rad
  double max_range = 80.0;  // m
  // The weights of the OctoMap (MapConfig: the pipeline passes its own).
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double free_probability = 0.2;  // a cell at most this likely occupied is free
};

// Throws Error naming the bad setting.
void validate(const VisibilityConfig& config);

// Built in two sweeps over the log: every scan's hits first, then every scan's rays (only
// cells hit at some time are counted, so memory follows the map, not the space crossed).
class VisibilityMap {
 public:
  explicit VisibilityMap(const VisibilityConfig& config);
  ~VisibilityMap();
  VisibilityMap(VisibilityMap&&) noexcept;
  VisibilityMap& operator=(VisibilityMap&&) noexcept;

  // One scan's hits (world frame), seen from `origin` (the sensor; nullopt: not known): each
  // cell it hits counts once. The n-th call is scan n (from 0): count and add_rays number
  // their calls the same way, so give them the scans in the same order (count throws
  // std::logic_error when called more often than add_hits). Not thread-safe.
  void add_hits(const Eigen::Matrix3Xf& points, const std::optional<Eigen::Vector3d>& origin = std::nullopt);

  // add_hits in two halves, as cast and count are: one scan's hit cells and their boxes
  // (read-only, scans side by side: the voxel grid and the boxes are most of the work), then
  // their counts (one scan at a time, in scan order).
  struct ScanHits {
    struct Cell {
      VoxelKey cell;
      CellSet::Key key;                 // the same cell as an OctoMap key
      std::array<std::uint8_t, 6> box;  // lo xyz, hi xyz of the scan's hits in it
      std::uint8_t seen_from = 0;
    };
    std::vector<Cell> cells;  // within the OctoMap's reach only
  };
  ScanHits hits_of(const Eigen::Matrix3Xf& points, const std::optional<Eigen::Vector3d>& origin) const;
  void add_hits(const ScanHits& hits);

  // Once every scan's hits are in: the faces of each cell whose hits are a line or a dot (see
  // above). add_rays calls it when needed; cast requires it (throws std::logic_error).
  void fit_surfaces();

  // One scan's rays, from `origin` (the sensor, world frame) to each of `points` (world
  // frame), one ray per cell the scan hits: each hit cell the scan crossed counts once. After
  // every scan's hits; not thread-safe. The same as count(cast(points, origin)).
  void add_rays(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin);

  // add_rays in two halves: casting (read-only, scans side by side) and counting (one at a
  // time).
  struct ScanRays {
    CellSet crossed;  // hit cells (at any time) a ray passed through within their box
    CellSet through;  // those a ray passed through without the margin
    CellSet hit;      // cells this scan hit
  };
  ScanRays cast(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) const;
  // Each ray from where the sensor was at its point's time (`times`, seconds after the stamp,
  // one per point; empty: all at the stamp): the sweep cut into spans the sensor crosses in
  // kOriginStep, each cast from the span's middle.
  ScanRays cast(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times, const SweepOrigin& sensor) const;
  // 2 cm: a ray's origin off by at most 1 cm, under the pose error between scans that
  // extent_margin already allows (2-3 cm). 25 spans for a sweep at 5 m/s.
  static constexpr double kOriginStep = 0.02;  // m
  void count(const ScanRays& rays);

  // 1 where a point lies in a free cell with no occupied cell around it. Read-only: safe from
  // many threads once the rays are in. A cell is free when a ray went through it and either
  // the OctoMap's weights say so or it left (Counts::left): a car 36 m away on SemanticKITTI 01
  // is hit by one scan and gone through by 2-5 (it drove on), which the OctoMap weighs as
  // occupied (0.85 a hit against 0.41 a crossing, free under -1.39).
  std::vector<std::uint8_t> moved_through(const Eigen::Matrix3Xf& points) const;

  static constexpr std::uint16_t kLastScan = 65534;
  struct Counts {
    std::uint16_t hits = 0, crossed = 0;
    std::uint16_t through = 0;  // of the crossings, those through the hits themselves (no margin)
    // The box the log's hits filled, in 256ths of the cell from its low corner (empty: lo > hi).
    std::array<std::uint8_t, 3> lo{255, 255, 255}, hi{0, 0, 0};
    std::uint8_t faces = 0;  // bit a: its hits face along axis a (fit_surfaces); 0: not known
    std::uint8_t seen_from = 0;  // bit a: hit by a ray going towards +a; bit a + 3: towards -a
    // The first and last scan that hit it (add_hits numbers them; past kLastScan, 1.8 h at
    // 10 Hz, every scan is kLastScan: rays of those scans are never "after" a hit).
    std::uint16_t first_hit = kLastScan + 1, last_hit = 0;
    // Of the scans gone through, those before its first hit or after its last: a mover's
    // cell is gone through once it left (or before it came), a thin pole's also between the
    // scans that hit it, where rays grazed past it.
    std::uint16_t through_apart = 0;
    // Hit in at least as many scans as gone through: what pass 2 pins in the clean map
    // (seen_standing).
    bool stood() const { return through <= hits; }
    // Gone through in more scans than hit, outside the span of scans that hit it: what
    // moved_through calls free where the OctoMap's weights do not.
    bool left() const { return through_apart > hits; }
  };
  Counts counts(const Eigen::Vector3f& p) const;  // zero for a cell never hit
  std::size_t cells() const { return cells_.size(); }
  double resolution() const { return config_.resolution; }

 private:
  VisibilityConfig config_;
  std::unique_ptr<octomap::OcTree> grid_;  // empty: its key arithmetic only
  tsl::robin_map<VoxelKey, Counts, VoxelKeyHash> cells_;
  // The rays of one span of a sweep, from one origin (cast).
  void cast_span(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& span, const Eigen::Vector3d& origin,
                 CellSet& walked, CellSet::Reader& ever_hit, ScanRays& out) const;
  bool surfaces_fitted_ = false;
  std::uint16_t hit_scans_ = 0, ray_scans_ = 0;  // calls of add_hits and of count, up to kLastScan
  CellSet hit_cells_;  // the same cells as bits: most crossed cells were never hit, one bit says so
  // The axes the hits of cell `k` face along (bit a), from its neighbours' hits.
  std::uint8_t faces(const VoxelKey& k, const Counts& c) const;
  // How the segment (t in [t0, t1] along from + dir t) passes the hits of cell `k` (OctoMap
  // key): through their level where they are thin, by angular_margin times the range
  // (kThrough), only within extent_margin of it (kNear), or not at all.
  enum class Crossing : std::uint8_t { kNone, kNear, kThrough };
  Crossing crossing(const CellSet::Key& k, const Eigen::Vector3d& from, const Eigen::Vector3d& dir, double t0,
                    double t1) const;
};

}  // namespace cleanmap
