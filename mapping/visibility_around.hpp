#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "mapping/sweep_origin.hpp"
#include "mapping/visibility_map.hpp"

namespace cleanmap {

// One scan as the visibility map takes it: world-frame points, their times after the scan's
// stamp (empty: none), the sensor's position (its hits' side) and where it was over the sweep
// (its rays').
struct ScanView {
  const Eigen::Matrix3Xf* points = nullptr;
  const Eigen::VectorXf* times = nullptr;  // nullptr: none
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  SweepOrigin sensor;
};

// The visibility of `scans` (in their order) for the cells of `around`: every hit, but only
// the rays that can reach those cells (the direction within the cells' angular size, the range
// beyond them). A ray is walked from its far end and stops where the scan's earlier rays
// walked on (carve_ray); with fewer rays cast it stops later, so a cell of `around` may count
// a crossing the map of every ray missed, never one fewer. A scan of 131k points casts a few
// thousand rays instead of 40k: an online run judges its last scan's dynamic objects with it.
VisibilityMap visibility_around(const Eigen::Matrix3Xf& around, const std::vector<ScanView>& scans,
                                const VisibilityConfig& config);

}  // namespace cleanmap
