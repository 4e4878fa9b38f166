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
                               double radius, const std::vector<std::uint8_t>& keeps_own = {});

}  // namespace cleanmap
