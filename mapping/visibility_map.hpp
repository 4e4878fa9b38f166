#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"
#include "mapping/cell_set.hpp"

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
struct VisibilityConfig {
  double resolution = 0.2;  // m
  double margin = 0.3;      // m
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

  // One scan's hits (world frame): each cell it hits counts once. Not thread-safe.
  void add_hits(const Eigen::Matrix3Xf& points);

  // One scan's rays, from `origin` (the sensor, world frame) to each of `points` (world
  // frame), one ray per cell the scan hits: each hit cell the scan crossed counts once. After
  // every scan's hits; not thread-safe. The same as count(cast(points, origin)).
  void add_rays(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin);

  // add_rays in two halves: casting (read-only, scans side by side) and counting (one at a
  // time).
  struct ScanRays {
    CellSet crossed, hit;
  };
  ScanRays cast(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin) const;
  void count(const ScanRays& rays);

  // 1 where a point lies in a free cell with no occupied cell around it. Read-only: safe from
  // many threads once the rays are in.
  std::vector<std::uint8_t> moved_through(const Eigen::Matrix3Xf& points) const;

  struct Counts {
    std::uint16_t hits = 0, crossed = 0;
  };
  Counts counts(const Eigen::Vector3f& p) const;  // zero for a cell never hit
  std::size_t cells() const { return cells_.size(); }
  double resolution() const { return config_.resolution; }

 private:
  VisibilityConfig config_;
  std::unique_ptr<octomap::OcTree> grid_;  // empty: its key arithmetic only
  tsl::robin_map<VoxelKey, Counts, VoxelKeyHash> cells_;
  CellSet hit_cells_;  // the same cells as bits: most crossed cells were never hit, one bit says so
};

}  // namespace cleanmap
