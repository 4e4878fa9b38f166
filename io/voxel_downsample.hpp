#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// Indices (ascending) of the first point falling in each voxel of the given size: the kept
// points are real measurements, so their times and intensities come along unchanged.
std::vector<std::int32_t> voxel_downsample(const Eigen::Matrix3Xf& points, double voxel_size);

// Diagonal of the axis-aligned bounding box of the points (the paper's scale(P)).
double bounding_box_diagonal(const Eigen::Matrix3Xf& points);

}  // namespace cleanmap
