#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"

namespace cleanmap {

// Points bucketed in cubes a little wider than one search radius: every point strictly within
// the radius of a query lies in the query's cube or one of its 26 neighbours. Built in one
// pass and a counting sort, for the flood fills of clustering, which search from the few
// points a seed reaches among many: building a kd-tree (PointIndex) over all of them was 4% of
// the online run's CPU. A point is within when its squared distance, summed over x, y, z in
// float as nanoflann's L2_Simple_Adaptor sums it, is below radius^2: the same neighbours as a
// PointIndex search.
class RadiusGrid {
 public:
  // Over points.col(members[m]); searches report m. `points` must outlive the grid.
  RadiusGrid(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& members, float radius);

  // Calls fn(m, squared_distance) for every member strictly within the radius of q.
  template <typename Fn>
  void for_each_within(const Eigen::Vector3f& q, Fn&& fn) const {
    for_each_within(
        q, [](std::uint32_t) { return false; }, fn);
  }

  // The same, but the members of a cube for which skip(cube) is true are not visited
  // (cube_of(m) names a member's cube; cubes() counts them).
  template <typename Skip, typename Fn>
  void for_each_within(const Eigen::Vector3f& q, Skip&& skip, Fn&& fn) const {
    const VoxelKey c = voxel_of(q, inv_cell_);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(VoxelKey{c.x + dx, c.y + dy, c.z + dz});
          if (it == cells_.end() || skip(it->second)) continue;
          for (std::uint32_t k = start_[it->second]; k < start_[it->second + 1]; ++k) {
            float dist = 0.0f;
            for (int d = 0; d < 3; ++d) {
              const float diff = q[d] - sorted_(d, k);
              dist += diff * diff;
            }
            if (dist < radius_sq_) fn(member_[k], dist);
          }
        }
      }
    }
  }

  std::uint32_t cube_of(std::uint32_t m) const { return cube_[m]; }
  std::size_t cubes() const { return start_.size() - 1; }
  std::uint32_t cube_size(std::uint32_t cube) const { return start_[cube + 1] - start_[cube]; }

 private:
  double inv_cell_;
  float radius_sq_;
  tsl::robin_map<VoxelKey, std::uint32_t, VoxelKeyHash> cells_;  // cube -> its range in sorted_
  std::vector<std::uint32_t> start_;   // per cube, then the end
  Eigen::Matrix3Xf sorted_;            // the members' points, cube by cube
  std::vector<std::uint32_t> member_;  // position in `members` of each sorted point
  std::vector<std::uint32_t> cube_;    // per member, its cube
};

}  // namespace cleanmap
