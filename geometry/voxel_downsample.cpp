#include "geometry/voxel_downsample.hpp"

#include <climits>

#include <tsl/robin_map.h>
#include <tsl/robin_set.h>

#include "geometry/voxel_key.hpp"

namespace cleanmap {

std::vector<std::int32_t> voxel_downsample(const Eigen::Matrix3Xf& points, double voxel_size) {
  const double inv = 1.0 / voxel_size;
  tsl::robin_set<VoxelKey, VoxelKeyHash> seen;
  seen.reserve(static_cast<std::size_t>(points.cols()) / 8);
  std::vector<std::int32_t> keep;
  // Scans come in firing or ring order: neighbours in the array often share a voxel, and a
  // comparison with the last voxel is much cheaper than a hash probe.
  VoxelKey last{INT32_MIN, INT32_MIN, INT32_MIN};
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const VoxelKey v = voxel_of(points.col(i), inv);
    if (v == last) continue;
    last = v;
    if (seen.insert(v).second) keep.push_back(static_cast<std::int32_t>(i));
  }
  return keep;
}

VoxelSample voxel_downsample_with_owners(const Eigen::Matrix3Xf& points, double voxel_size) {
  const double inv = 1.0 / voxel_size;
  tsl::robin_map<VoxelKey, std::int32_t, VoxelKeyHash> slot;
  slot.reserve(static_cast<std::size_t>(points.cols()) / 8);
  VoxelSample out;
  out.owner.resize(static_cast<std::size_t>(points.cols()));
  VoxelKey last{INT32_MIN, INT32_MIN, INT32_MIN};
  std::int32_t last_owner = -1;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const VoxelKey v = voxel_of(points.col(i), inv);
    if (!(v == last)) {
      const auto [it, fresh] = slot.try_emplace(v, static_cast<std::int32_t>(out.keep.size()));
      if (fresh) out.keep.push_back(static_cast<std::int32_t>(i));
      last = v;
      last_owner = it->second;
    }
    out.owner[static_cast<std::size_t>(i)] = last_owner;
  }
  return out;
}

double bounding_box_diagonal(const Eigen::Matrix3Xf& points) {
  if (points.cols() == 0) return 0.0;
  return static_cast<double>((points.rowwise().maxCoeff() - points.rowwise().minCoeff()).norm());
}

}  // namespace cleanmap
