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

// Throws Error naming `who` (the settings' owner) and the bad value.
void validate(const ObjectRule& rule, const std::string& who);

}  // namespace cleanmap
