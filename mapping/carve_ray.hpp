#pragma once

#include <Eigen/Core>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "mapping/cell_set.hpp"

namespace cleanmap {

// The most cells a map's settings may make one ray walk (max_range / resolution): 30 m at 3 mm,
// 300 m at 3 cm, finer than any sensor's range noise. A scan casts thousands of rays (issue 45:
// --resolution 0.001 passed the reach check and a run never ended). Both maps check it.
inline constexpr double kMaxCellsPerRay = 10000.0;

// Walks the cells the segment from -> to crosses on the tree's grid (a 3D DDA, the traversal
// of OctoMap's computeRayKeys run from the far end), from `from`'s cell (included when
// `include_first`) to `to`'s cell (included), adding them to `carved`. Stops after a few
// cells in a row already in `carved`: the rays of one scan share its origin and converge
// towards it, so the rest of the way was carved by earlier rays. That turns the cost from
// rays x length into about the number of distinct cells. Into an empty set, the cells are
// those of computeRayKeys(to, from) plus `to`'s cell.
void carve_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               bool include_first, CellSet& carved);

// carve_ray that also shows each cell to `visit(key, t_in, t_out)`, with the part of the
// segment inside it (from + (to - from) * t, t in [t_in, t_out] within [0, 1]). visit returns
// whether the cell is settled for this scan: a cell an earlier ray carved counts towards the
// stop only when it is, so a cell that wants more rays than the first keeps getting them.
template <typename Visit>
void walk_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
              bool include_first, CellSet& carved, Visit&& visit);

namespace carve_detail {
// Cells in a row an earlier ray already carved before this one stops. One is not enough: two
// converging rays a fraction of a cell apart share a cell, then step apart again, and
// stopping at the first shared cell left whole fans of cells uncarved (free-space IoU on the
// synthetic street 0.79 -> 0.55); four keeps the full traversal's result at a quarter of
// its cost.
constexpr int kStopAfterKnown = 4;
}  // namespace carve_detail

template <typename Visit>
void walk_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
              bool include_first, CellSet& carved, Visit&& visit) {
  octomap::OcTreeKey key, last;
  if (!tree.coordToKeyChecked(from.x(), from.y(), from.z(), key) ||
      !tree.coordToKeyChecked(to.x(), to.y(), to.z(), last)) {
    return;
  }
  const Eigen::Vector3d dir = to - from;
  const double res = tree.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  int steps = 0;
  for (int i = 0; i < 3; ++i) {
    steps += std::abs(static_cast<int>(last[i]) - static_cast<int>(key[i]));
    step[i] = dir[i] > 0 ? 1 : dir[i] < 0 ? -1 : 0;
    if (step[i] == 0) {
      t_max[i] = t_delta[i] = std::numeric_limits<double>::infinity();
      continue;
    }
    const double border = tree.keyToCoord(key[i]) + step[i] * res / 2;  // cell centre +- half
    t_max[i] = (border - from[i]) / dir[i];
    t_delta[i] = res / std::abs(dir[i]);
  }
  auto exit_t = [&] { return std::min(1.0, std::min(t_max[0], std::min(t_max[1], t_max[2]))); };
  int known = 0;
  if (include_first) {
    const CellSet::Key k{key[0], key[1], key[2]};
    const bool fresh = carved.insert(k);
    known = visit(k, 0.0, exit_t()) && !fresh ? 1 : 0;
  }
  // The key distance bounds the walk exactly (each step moves one axis by one cell), so
  // rounding at cell borders can never make it run on.
  for (; steps > 0; --steps) {
    int a = 0;
    for (int i = 1; i < 3; ++i) {
      if (t_max[i] < t_max[a]) a = i;
    }
    if (key[a] == last[a]) {  // rounding: this axis is done, move another one
      a = -1;
      for (int i = 0; i < 3; ++i) {
        if (key[i] != last[i] && (a < 0 || t_max[i] < t_max[a])) a = i;
      }
    }
    const double t_in = std::min(1.0, t_max[a]);
    key[a] = static_cast<octomap::key_type>(key[a] + step[a]);
    t_max[a] += t_delta[a];
    const CellSet::Key k{key[0], key[1], key[2]};
    const bool fresh = carved.insert(k);
    const bool settled = visit(k, t_in, std::max(t_in, exit_t()));
    known = fresh || !settled ? 0 : known + 1;
    if (known == carve_detail::kStopAfterKnown) return;
  }
}

}  // namespace cleanmap
