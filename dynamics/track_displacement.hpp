#pragma once

// Track-level evidence (issue 47): how far one object moved between two sightings, from its
// points rather than its centroid. A cluster's centroid jitters as points join and leave (up to
// the 0.6 m linking distance on static vegetation), so the tracker's centroid rule needs a
// shift of a cluster radius within the window: 1.5 m/s at 10 Hz and N = 4, above a walker's
// pace. Registered points follow the surface instead, which sensor noise and pose error blur
// by centimetres.

#include <Eigen/Core>

namespace cleanmap {

// The translation that best carries `from` onto `to` (point-to-point, pairs nearer than
// `reach` after the shift; from zero, so shifts well under `reach` are found), and the share of
// `from` that then has a partner within `reach`. Both sets are small samples of one object
// (ObjectTracker keeps up to 32 points per sighting): the nearest neighbours are searched
// exhaustively.
struct Shift {
  Eigen::Vector3f by = Eigen::Vector3f::Zero();
  float overlap = 0.0f;  // in [0, 1]
};
Shift register_shift(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to, float reach);

// The largest shift between two scans' sightings of a standing object at `range` that sensor
// noise and pose error explain (3 sigma): each scan's pose off by `pose_noise` m and
// `pose_noise_deg` (at range r, r x angle), 2 cm of range noise, and 3 mrad of beam divergence
// (the VLS-128's horizontal spread, its manual's table F-1) times the range. 10 m, 2 cm pose
// noise: 0.14 m; 30 m: 0.29 m.
float displacement_floor(double range, double pose_noise, double pose_noise_deg);

}  // namespace cleanmap
