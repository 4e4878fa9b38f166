#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace cleanmap {

// The DynamicMap benchmark's score of a cleaned map (Zhang et al., KTH): every ground-truth
// point counts as kept when the output cloud has a point within 0.05 m of it, else removed.
// SA = kept static / static, DA = removed dynamic / dynamic (both in %), AA = sqrt(SA DA),
// HA = 2 SA DA / (SA + DA).
//
// `da_ceiling` is the DA of the ground truth's own static points as the output: the most any
// method removes while it keeps every static point (SA 100). Where a mover's points lie within
// the distance of static ones (a truck that crawls, then stands; the ground under a box's
// margin), no method reaches DA above it without giving up SA.
struct MapScore {
  double sa = 0, da = 0, aa = 0, ha = 0, da_ceiling = 0;
  std::size_t static_points = 0, dynamic_points = 0, static_kept = 0, dynamic_removed = 0;
};

MapScore score_map(const Eigen::Matrix3Xf& gt_points, const std::vector<std::uint8_t>& gt_dynamic,
                   const Eigen::Matrix3Xf& output, double distance = 0.05);

}  // namespace cleanmap
