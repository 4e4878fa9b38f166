#pragma once

#include <Eigen/Core>

#include "mapping/cell_set.hpp"

namespace octomap {
class OcTree;
}

namespace cleanmap {

// Walks the cells the segment from -> to crosses on the tree's grid (a 3D DDA, the traversal
// of OctoMap's computeRayKeys run from the far end), from `from`'s cell (included when
// `include_first`) to `to`'s cell (included), adding them to `carved`. Stops after a few
// cells in a row already in `carved`: the rays of one scan share its origin and converge
// towards it, so the rest of the way was carved by earlier rays. That turns the cost from
// rays x length into about the number of distinct cells. Into an empty set, the cells are
// those of computeRayKeys(to, from) plus `to`'s cell.
void carve_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               bool include_first, CellSet& carved);

}  // namespace cleanmap
