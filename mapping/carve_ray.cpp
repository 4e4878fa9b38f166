#include "mapping/carve_ray.hpp"

#include <octomap/OcTree.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace cleanmap {
namespace {
// Cells in a row an earlier ray already carved before this one stops. One is not enough: two
// converging rays a fraction of a cell apart share a cell, then step apart again, and
// stopping at the first shared cell left whole fans of cells uncarved (free-space IoU on the
// synthetic street 0.79 -> 0.55); four keeps the full traversal's result at a quarter of
// its cost.
constexpr int kStopAfterKnown = 4;
}  // namespace

void carve_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               bool include_first, CellSet& carved) {
  octomap::OcTreeKey key, last;
  if (!tree.coordToKeyChecked(from.x(), from.y(), from.z(), key) ||
      !tree.coordToKeyChecked(to.x(), to.y(), to.z(), last)) {
    return;
  }
  int known = include_first && !carved.insert({key[0], key[1], key[2]}) ? 1 : 0;
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
    key[a] = static_cast<octomap::key_type>(key[a] + step[a]);
    t_max[a] += t_delta[a];
    known = carved.insert({key[0], key[1], key[2]}) ? 0 : known + 1;
    if (known == kStopAfterKnown) return;
  }
}

}  // namespace cleanmap
