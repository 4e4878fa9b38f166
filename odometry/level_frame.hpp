#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace cleanmap {

// A camera's first frame is not level (a depth camera on an arm looks down at the table), yet
// ground decisions need "up". The support a camera looks at (the table top, the floor) is the
// plane holding most of its points among those below it: found by RANSAC (fixed seed, `inlier`
// m), its normal turned towards the camera is up. "Below" is the prior that a camera is held
// upright (an arm's or a hand's): in the optical frame (x right, y down, z forward) up is near
// -y, and a plane whose normal is more than 60 degrees from it is a wall or a ceiling. Returns
// the rotation that makes the support's normal +z, or nothing when no such plane holds a fifth
// of the points (then the frame stays as it is).
std::optional<Eigen::Matrix3d> level_rotation(const Eigen::Matrix3Xf& sensor_points, double inlier = 0.01);

}  // namespace cleanmap
