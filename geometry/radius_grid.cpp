#include "geometry/radius_grid.hpp"

namespace cleanmap {

RadiusGrid::RadiusGrid(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& members, float radius)
    // A hair wider than the radius: two points closer than it differ by at most one cube on
    // every axis even where p / cell rounds up across a cube's border.
    : inv_cell_(1.0 / (static_cast<double>(radius) * (1.0 + 1e-6))), radius_sq_(radius * radius) {
  const std::size_t n = members.size();
  std::vector<std::uint32_t>& cube = cube_;
  cube.resize(n);
  std::vector<std::uint32_t> count;
  cells_.reserve(n / 4);
  for (std::size_t m = 0; m < n; ++m) {
    const VoxelKey key = voxel_of(points.col(members[m]), inv_cell_);
    const auto [it, fresh] = cells_.try_emplace(key, static_cast<std::uint32_t>(count.size()));
    if (fresh) count.push_back(0);
    cube[m] = it->second;
    ++count[it->second];
  }
  start_.assign(count.size() + 1, 0);
  for (std::size_t c = 0; c < count.size(); ++c) start_[c + 1] = start_[c] + count[c];
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  sorted_.resize(3, static_cast<Eigen::Index>(n));
  member_.resize(n);
  for (std::size_t m = 0; m < n; ++m) {
    const std::uint32_t k = next[cube[m]]++;
    sorted_.col(k) = points.col(members[m]);
    member_[k] = static_cast<std::uint32_t>(m);
  }
}

}  // namespace cleanmap
