#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dynamics/cell_table.hpp"
#include "dynamics/spatiotemporal_normal.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {

// The scorer's fast-mode neighbourhoods, by statistics cell. The points of one cell share its
// neighbour cells: they are looked up once per cell, their moments shifted once to the cell's
// origin (a covariance does not depend on the origin), and each point only selects and adds
// them. Per point, the look-ups and the shifts had been most of the scorer's time (perf on the
// Pandar64 street at 0.1 m voxels: 23 % of an online run in the per-point loop).

// A cell's centre (time 0): the origin its moments are kept relative to.
inline Eigen::Vector4d cell_origin(const VoxelKey& k, double cell) {
  return {(k.x + 0.5) * cell, (k.y + 0.5) * cell, (k.z + 0.5) * cell, 0.0};
}

// One neighbour cell of a query cell.
struct NearCell {
  VoxelKey off;          // from the query cell
  Eigen::Vector3d mean;  // of the cell's points, world frame
  Moments4 m;            // relative to the query cell's origin at time `t` (near_cells)
};

// Every cell `centre + offsets[k]` of `table` that holds points, shifted to the origin
// (centre of `centre`, time t).
void near_cells(const CellTable& table, const std::vector<VoxelKey>& offsets, double cell,
                const VoxelKey& centre, double t, std::vector<NearCell>& out);

// The moments of query `q` (in cell `centre`) from its cell's neighbours: a cell takes part when
// its box reaches within `radius` of the query and the mean of its points lies within it.
// Relative to the query cell's origin. `chosen`: bit j set when near[j] takes part (the first 64).
Moments4 neighbourhood_of(const Eigen::Vector3d& q, const VoxelKey& centre, double cell,
                          double radius, const std::vector<NearCell>& near, std::uint64_t& chosen);

// Points by cell: `order` lists them cell by cell, cell c's points at order[start[c]] ..
// order[start[c + 1]]; `cell_of[i]` in [0, cells) is point i's cell.
struct CellGroups {
  std::vector<std::int32_t> order, start;
};
CellGroups cell_groups(const std::vector<std::int32_t>& cell_of, std::int32_t cells);

}  // namespace cleanmap
