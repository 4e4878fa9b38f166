#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

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

// Which clusters (ids 0..k-1 from clusters_from_seeds, -1 = none) are one moving object by
// the vote of their points: at least `min_votes` points vote (votes[i] != 0), at least
// `min_fraction` of the points that count do (counts[i] != 0; empty = every point counts), and
// the cluster spans at most `max_extent` horizontally (a building is never one object).
std::vector<std::uint8_t> vote_clusters(const Eigen::Matrix3Xf& points,
                                        const std::vector<std::int32_t>& id,
                                        const std::vector<std::uint8_t>& votes,
                                        const std::vector<std::uint8_t>& counts, int min_votes,
                                        double min_fraction, double max_extent);

}  // namespace cleanmap
