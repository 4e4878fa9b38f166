#include "dynamics/cell_neighbourhood.hpp"

namespace cleanmap {

void near_cells(const CellTable& table, const std::vector<VoxelKey>& offsets, double cell,
                const VoxelKey& centre, double t, std::vector<NearCell>& out) {
  out.clear();
  Eigen::Vector4d origin = cell_origin(centre, cell);
  origin[3] = t;
  for (const auto& off : offsets) {
    const VoxelKey key{centre.x + off.x, centre.y + off.y, centre.z + off.z};
    const Moments4* c = table.find(key);
    if (!c) continue;
    const Eigen::Vector4d o = cell_origin(key, cell);
    out.push_back({off, o.head<3>() + c->sum.head<3>() / c->n, c->shifted(origin - o)});
  }
}

Moments4 neighbourhood_of(const Eigen::Vector3d& q, const VoxelKey& centre, double cell,
                          double radius, const std::vector<NearCell>& near, std::uint64_t& chosen) {
  const double r_sq = radius * radius;
  // Where the query sits in its cell, in cells: skip cells whose box is beyond the radius.
  const Eigen::Vector3d frac = q / cell - Eigen::Vector3d(centre.x, centre.y, centre.z);
  const double r_cells_sq = r_sq / (cell * cell);
  Moments4 m;
  chosen = 0;
  for (std::size_t j = 0; j < near.size(); ++j) {
    const NearCell& c = near[j];
    double gap_sq = 0.0;
    for (int d = 0; d < 3; ++d) {
      const int o = d == 0 ? c.off.x : d == 1 ? c.off.y : c.off.z;
      const double g = o > 0 ? o - frac[d] : o < 0 ? -o - 1.0 + frac[d] : 0.0;
      gap_sq += g > 0 ? g * g : 0.0;
    }
    if (gap_sq > r_cells_sq) continue;
    if ((c.mean - q).squaredNorm() > r_sq) continue;
    m += c.m;
    if (j < 64) chosen |= std::uint64_t{1} << j;
  }
  return m;
}

CellGroups cell_groups(const std::vector<std::int32_t>& cell_of, std::int32_t cells) {
  CellGroups out;
  out.start.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (const auto c : cell_of) ++out.start[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 1; c < out.start.size(); ++c) out.start[c] += out.start[c - 1];
  out.order.resize(cell_of.size());
  auto fill = out.start;
  for (std::size_t i = 0; i < cell_of.size(); ++i) {
    out.order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[i])]++)] =
        static_cast<std::int32_t>(i);
  }
  return out;
}

}  // namespace cleanmap
