#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "odometry/odometry_config.hpp"
#include "odometry/voxel_hash_map.hpp"

namespace cleanmap {

struct RegistrationResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  int iterations = 0;
  int correspondences = 0;
  double rms_residual = 0.0;  // m, point-to-plane, last iteration
  double inlier_share = 0.0;  // source points matched to a map plane within the final gate
  bool converged = false;
  bool degenerate = false;    // too few correspondences or an unconstrained direction
};

// Correspondence gates of one registration: matched first within `start`, halved each time the
// pose settles, until it settles within `end` (coarse to fine: a wide basin when the prediction
// may be poor, the final weighing with the gate the motion model has earned).
struct GateSchedule {
  double start = 2.0;  // m
  double end = 2.0;    // m
};

// Registers sensor-frame points to the map: point-to-plane residuals n^T (T p - m) against
// planes fitted to the map's nearest points (weighted by planarity; neighbours within a voxel,
// the nearest within the gate), a Cauchy loss of scale gate / 3, solved with Ceres over
// T = (Eigen quaternion, translation); correspondences are searched again after each solve
// until the pose settles with the last gate (at most config.max_icp_iterations rounds).

RegistrationResult register_point_to_plane(const std::vector<Eigen::Vector3d>& source,
                                           const VoxelHashMap& map,
                                           const Eigen::Isometry3d& initial,
                                           const GateSchedule& gates,
                                           const OdometryConfig& config);

// Plain point-to-point ICP (closed-form Umeyama alignment per iteration, no robust loss,
// no planes): the baseline the benchmark compares against.
RegistrationResult register_point_to_point(const std::vector<Eigen::Vector3d>& source,
                                           const VoxelHashMap& map,
                                           const Eigen::Isometry3d& initial, double threshold,
                                           const OdometryConfig& config);

}  // namespace cleanmap
