#include "io/voxel_downsample.hpp"

#include <tsl/robin_map.h>
#include <tsl/robin_set.h>

#include "io/voxel_key.hpp"

namespace cleanmap {

std::vector<std::int32_t> voxel_downsample(const Eigen::Matrix3Xf& points, double voxel_size) {
  const double inv = 1.0 / voxel_size;
  tsl::robin_set<VoxelKey, VoxelKeyHash> seen;
  seen.reserve(static_cast<std::size_t>(points.cols()) / 2);
  std::vector<std::int32_t> keep;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (seen.insert(voxel_of(points.col(i), inv)).second) keep.push_back(static_cast<std::int32_t>(i));
  }
  return keep;
}

VoxelSample voxel_downsample_with_owners(const Eigen::Matrix3Xf& points, double voxel_size) {
  const double inv = 1.0 / voxel_size;
  tsl::robin_map<VoxelKey, std::int32_t, VoxelKeyHash> slot;
  slot.reserve(static_cast<std::size_t>(points.cols()) / 2);
  VoxelSample out;
  out.owner.resize(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const auto [it, fresh] = slot.try_emplace(voxel_of(points.col(i), inv), static_cast<std::int32_t>(out.keep.size()));
    if (fresh) out.keep.push_back(static_cast<std::int32_t>(i));
    out.owner[static_cast<std::size_t>(i)] = it->second;
  }
  return out;
}

double bounding_box_diagonal(const Eigen::Matrix3Xf& points) {
  if (points.cols() == 0) return 0.0;
  return static_cast<double>((points.rowwise().maxCoeff() - points.rowwise().minCoeff()).norm());
}

}  // namespace cleanmap
