#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// Indices (ascending) of the first point falling in each voxel of the given size: the kept
// points are real measurements, so their times and intensities come along unchanged.
std::vector<std::int32_t> voxel_downsample(const Eigen::Matrix3Xf& points, double voxel_size);

// The same downsampling, plus for every input point the position in `keep` of its voxel's
// kept point: the way back from the downsampled cloud to full resolution, with no search.
struct VoxelSample {
  std::vector<std::int32_t> keep;
  std::vector<std::int32_t> owner;  // per input point, index into keep
};
VoxelSample voxel_downsample_with_owners(const Eigen::Matrix3Xf& points, double voxel_size);

// Diagonal of the axis-aligned bounding box of the points (the paper's scale(P)).
double bounding_box_diagonal(const Eigen::Matrix3Xf& points);

}  // namespace cleanmap
