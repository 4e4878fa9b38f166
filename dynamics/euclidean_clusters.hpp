#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "dynamics/object_rule.hpp"

namespace cleanmap {

// Connected components (points closer than `radius` linked) of the points with include[i] != 0
// that contain a seed (seed[i] != 0 and included); every other point stays -1. Ids are
// 0..k-1 in the order of each cluster's lowest seed index, so the result does not depend on
// search order. Grown from the seeds only: where objects are a few, that is a few hundred
// searches, not a clustering of the whole scan; a cluster without a seed could not change
// anything for the callers (completion, the free-space vote) anyway.
std::vector<std::int32_t> clusters_from_seeds(const Eigen::Matrix3Xf& points,
                                              const std::vector<std::uint8_t>& include,
                                              const std::vector<std::uint8_t>& seed, float radius);

// clusters_from_seeds on a subsample: the included points are downsampled to `voxel`, a voxel
// holding a seed is one, the voxels' representatives are clustered and each included point
// takes its voxel's id. Where points are much denser than the radius (0.1 m voxels against a
// 0.6 m radius, a truck's side a few metres away) a full-resolution search returns hundreds of
// neighbours per point; on voxels of half the radius, a handful. Links are decided between
// representatives, so a gap differs from the full clustering's by at most a voxel diagonal
// each side.
std::vector<std::int32_t> clusters_on_voxels(const Eigen::Matrix3Xf& points,
                                             const std::vector<std::uint8_t>& include,
                                             const std::vector<std::uint8_t>& seed, float radius,
                                             double voxel);

// kFewVotes: fewer than min_votes points vote. A mover is seen as several neighbouring voxels
// (a pedestrian at 0.1 m voxels is dozens); one or two dynamic voxels alone are noise.
enum class ClusterVerdict : std::uint8_t { kNotMoving, kMoving, kTooLarge, kFewVotes };

// The verdict on each cluster (ids 0..k-1 from clusters_from_seeds, -1 = none) by the vote of
// its points: too large when it spans more than `max_extent` horizontally, whatever the vote;
// else few votes when fewer than `min_votes` points vote (votes[i] != 0); else moving when at
// least `min_fraction` of the points that count do (counts[i] != 0; empty = every point
// counts).
std::vector<ClusterVerdict> vote_clusters(const Eigen::Matrix3Xf& points,
                                          const std::vector<std::int32_t>& id,
                                          const std::vector<std::uint8_t>& votes,
                                          const std::vector<std::uint8_t>& counts,
                                          const ObjectRule& rule);

// Clusters of the included points that hold a seed, at a given radius (clusters_from_seeds, or
// a caller's cheaper equivalent on a subsample).
using ClusterFunction = std::function<std::vector<std::int32_t>(
    const std::vector<std::uint8_t>& include, const std::vector<std::uint8_t>& seed, float radius)>;

// The verdict on each point's cluster (kNotMoving for points in none). Clusters too large to
// be one object are split (re-clustered at half the radius) until they are small enough or the
// radius reaches rule.min_split_radius (then they stay kTooLarge). Callers add kMoving clusters
// to their per-point decisions; a cluster that fails the vote on its share takes nothing away.
std::vector<ClusterVerdict> moving_objects(const Eigen::Matrix3Xf& points,
                                         const std::vector<std::uint8_t>& include,
                                         const std::vector<std::uint8_t>& votes,
                                         const std::vector<std::uint8_t>& counts,
                                         const ObjectRule& rule, const ClusterFunction& cluster);

}  // namespace cleanmap
