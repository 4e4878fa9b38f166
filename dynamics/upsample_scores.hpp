#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace cleanmap {

struct PointDecisions {
  std::vector<float> score;           // NaN = not scored
  std::vector<std::uint8_t> dynamic;  // 1 = dynamic
};

// Carries decisions of downsampled points to full-resolution points. `owner[i]`: the
// downsampled point standing for full point i's voxel (voxel_downsample_with_owners).
// "nearest": each point takes score and decision of its nearest downsampled point within
// `radius` (else unscored). "paper" (Falque et al.): a point is dynamic when any dynamic
// downsampled point lies within `radius`; its score is its voxel's (the owner's). With the
// paper's rule, a point whose voxel's downsampled point is marked in `keeps_own` (one flag per
// downsampled point; empty = none) keeps its voxel's decision.
PointDecisions upsample_scores(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                               const std::vector<std::int32_t>& owner,
                               const PointDecisions& down_decisions, const std::string& method,
                               double radius, const std::vector<std::uint8_t>& keeps_own = {},
                               double voxel_size = 0.0);

// Per full point, the index of its nearest downsampled point. Each downsampled point is a full
// point that stands for its voxel of `voxel_size` (voxel_downsample_with_owners: `owner`). The
// owner lies in the point's own voxel, at most sqrt(3) voxels away, so only the voxels of the
// 5 x 5 x 5 block around it whose box is nearer than the owner can hold a nearer point.
// Equal distances go to the lower index.
std::vector<std::int32_t> nearest_on_voxels(const Eigen::Matrix3Xf& full,
                                            const Eigen::Matrix3Xf& down,
                                            const std::vector<std::int32_t>& owner,
                                            double voxel_size);

}  // namespace cleanmap
