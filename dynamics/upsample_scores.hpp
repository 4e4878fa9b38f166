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

// Carries decisions of downsampled points to full-resolution points.
// "nearest": each point takes score and decision of its nearest downsampled point within
// `radius` (else unscored). "paper" (Falque et al.): a point is dynamic when any dynamic
// downsampled point lies within `radius`; its score is still its nearest neighbour's.
PointDecisions upsample_scores(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                               const PointDecisions& down_decisions, const std::string& method,
                               double radius);

}  // namespace cleanmap
