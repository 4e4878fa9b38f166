#pragma once

#include <string>

namespace cleanmap {

// When a Euclidean cluster of non-ground points is one moving object. One rule for the
// scorer's object completion and the free-space vote, each with its own settings.
struct ObjectRule {
  double radius = 0.6;         // m: points closer than this are one cluster
  int min_votes = 3;           // points that must vote for the cluster
  double min_fraction = 0.1;   // share of the counted points that must vote
  // m, horizontal: a cluster wider than this is not one object (a building, or a person
  // beside a hedge linked to it); it is split by re-clustering at half the radius, down to
  // `min_split_radius`, and each part is judged on its own.
  double max_extent = 12.0;
  double min_split_radius = 0.15;
};

// How objects are followed across scans (ObjectTracker): an object continues the track of
// its nearest object in the previous scan (one-to-one) when its centroid is within
// max_speed * gap + the cluster radius and each fits in the other's box grown by as much.
// 15 m/s (54 km/h) covers urban traffic; a faster object starts a new track each scan, which
// costs nothing, for the normals see it moving in every scan.
struct TrackRule {
  bool enabled = true;
  double max_speed = 15.0;  // m/s
};

// Throws Error naming `who` (the settings' owner) and the bad value.
void validate(const ObjectRule& rule, const std::string& who);

}  // namespace cleanmap
