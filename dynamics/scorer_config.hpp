#pragma once

#include <string>

#include "dynamics/ground_segmentation.hpp"
#include "dynamics/object_rule.hpp"

namespace cleanmap {

// All the scorer's parameters, in physical units. Defaults are the paper's DOALS settings
// (Ouster OS1-64 at 10 Hz) plus this project's improvements, each switchable.
struct ScorerConfig {
  // The paper's four parameters.
  double voxel_size = 0.0;        // d_v in metres; 0 = relative: bounding-box diagonal / divisor
  double voxel_divisor = 600.0;   // the paper's scale(P)/600
  int window_half = 10;           // N: the window holds 2N+1 scans
  double radius = 0.3;            // d_r, metres
  double threshold = 0.25;        // thr on |n_t|

  double time_scale = 1.0;        // metres that one second weighs in the 4D PCA
  // The poses' error per scan (1 sigma): a point is dynamic only when its score also exceeds
  // the motion this error can fake over its neighbourhood's time spread (3 sigma). 0 = off.
  double pose_noise = 0.0;        // m
  double pose_noise_deg = 0.0;    // degrees; at range r adds r * angle
  int min_neighbors = 10;         // fewer neighbours: the point is not scored (NaN)
  // Not scored when the smallest 4D eigenvalue exceeds this share of the next one: the normal
  // is then ill-defined (vegetation, clutter). 0 = off, the paper's behaviour.
  double max_eigen_ratio = 0.0;
  std::string mode = "fast";      // "fast" (per-voxel sums) or "exact" (kd-tree radius search)
  double cell_size = 0.0;         // fast mode's statistics grid; 0 = radius

  // Carrying scores back to full resolution.
  std::string upsample = "paper";  // "paper" (any dynamic within the radius) or "nearest" scored neighbour
  double upsample_radius = 0.5;

  // Ground-aware neighbourhoods: ground and non-ground points are scored only against their
  // own kind, so ground does not tilt the normals of objects' feet.
  bool ground_aware = true;
  bool ground_static = true;   // with ground_aware: ground points are never dynamic on their own
  GroundConfig ground;         // where the ground is (also the free-space vote's ground)

  // Object-level completion: a Euclidean cluster of non-ground points is dynamic as a whole
  // when enough of it scores dynamic (votes: dynamic points; counted: scored points). A
  // cluster that fails the share keeps its points' own decisions; one with fewer than
  // objects.min_votes dynamic points is noise. Off = the paper's per-point output.
  bool object_completion = true;
  ObjectRule objects;
  // Objects followed across the window (ObjectTracker): the scorer describes every object of
  // each scan, the tracker carries a mover's label to the scans where the normals miss it.
  TrackRule tracks;
};

// Throws Error naming the bad parameter.
void validate(const ScorerConfig& config);

}  // namespace cleanmap
