#include "mapping/whole_log_vote.hpp"

#include "dynamics/euclidean_clusters.hpp"

namespace cleanmap {
namespace {

// Inside the log, a dynamic object stands only if rays went through its cells in at least one
// scan for every kHitsPerThrough scans that hit them. What left its place is seen through by
// the scans after it (or before it came); a static porous or ragged surface (a fence, a hedge,
// a kerb's edge the rings slide along) is hit in nearly every scan that sees it and let
// through now and then, between the scans that hit it: only scans before a cell's first hit
// or after its last count (Counts::through_apart). Inside-the-log dynamic clusters of the
// normals, through per hit summed over the cluster's points' cells (scratch dump of every
// cluster, the centre in a box or on labelled points, counting every scan's rays): movers
// never below 0.04 on any set (Pandar64: 63 points at 0.04-0.05 and 49 k at 0.08-0.1, truck
// 100 braking beside the sensor; SemanticKITTI and the synthetic street never below 0.09),
// while static clusters spread down to 0 (Pandar64: 18.7 k points in (0, 0.04], the synthetic
// street 91). Counting apart from the hits kept every recall of bench/quality.sh.
constexpr std::size_t kHitsPerThrough = 25;
// (A cell never hit, beyond the visibility map's range, has neither: never gone through.)
bool gone_through_too_rarely(std::size_t through, std::size_t hits) {
  return through == 0 || through * kHitsPerThrough < hits;
}

// Dynamic objects the log saw standing back to static: at a log end those seen through less
// often than hit, inside it those seen through in under one scan per kHitsPerThrough that hit
// them (never, for the most part). Clustered on a `voxel` subsample, as the free-space vote
// is: at full resolution a truck's side 3 m away has about 1000 points within the 0.6 m
// radius of each, and growing its clusters took half of an offline run's CPU on the Pandar64
// street. Counts stay per point.
std::size_t veto_unconfirmed(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                             const VisibilityMap& log, float radius, bool log_end, double voxel,
                             const std::vector<std::uint8_t>& on_moving_track) {
  std::vector<VisibilityMap::Counts> counts(dynamic.size());
  // Inside the log only clusters with a point seen through too rarely can be vetoed: grown from
  // those alone (most scans have a few).
  std::vector<std::uint8_t> seed(dynamic.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    if (!dynamic[i]) continue;
    counts[i] = log.counts(points.col(static_cast<Eigen::Index>(i)));
    seed[i] = log_end || gone_through_too_rarely(counts[i].through_apart, counts[i].hits);
    any |= seed[i] != 0;
  }
  if (!any) return 0;
  const auto id = clusters_on_voxels(points, dynamic, seed, radius, voxel);
  // What each cluster's points saw of the log, summed.
  struct ClusterCounts {
    std::size_t hits = 0, crossed = 0, through_apart = 0;
    bool tracked = false;  // holds a point of a track seen moving inside the log
  };
  std::vector<ClusterCounts> cluster;
  const bool ends_tracked = log_end && on_moving_track.size() == dynamic.size();
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    if (id[i] < 0) continue;
    const auto k = static_cast<std::size_t>(id[i]);
    if (k >= cluster.size()) cluster.resize(k + 1);
    auto& c = cluster[k];
    c.tracked |= ends_tracked && on_moving_track[i];
    c.hits += counts[i].hits;
    c.crossed += counts[i].crossed;
    c.through_apart += counts[i].through_apart;
  }
  std::size_t vetoed = 0;
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    if (id[i] < 0) continue;
    const auto& c = cluster[static_cast<std::size_t>(id[i])];
    // At the log's ends fewer crossings than hits (crossed: within the margin of the hits), or
    // for an object on a track seen moving inside the log, the rule inside it; inside the log
    // only rays through count.
    const bool ends_rule = log_end && !c.tracked;
    if (ends_rule ? c.crossed < c.hits : gone_through_too_rarely(c.through_apart, c.hits)) {
      dynamic[i] = 0;
      ++vetoed;
    }
  }
  return vetoed;
}

}  // namespace

WholeLogVerdict judge_with_log(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                               const VisibilityMap& log, const GroundQuery& ground_of,
                               const ObjectRule& rule, bool log_end, double voxel,
                               const std::vector<std::uint8_t>& on_moving_track) {
  WholeLogVerdict v;
  v.vetoed = veto_unconfirmed(points, dynamic, log, static_cast<float>(rule.radius), log_end, voxel,
                              on_moving_track);
  const auto objects = free_space_objects(
      points, ground_of, [&](const Eigen::Matrix3Xf& sub) { return log.moved_through(sub); }, rule, voxel);
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    v.added += objects[i] && !dynamic[i];
    dynamic[i] |= objects[i];
  }
  return v;
}

std::size_t judge_log_end(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                          const VisibilityMap& log, const ObjectRule& rule, double voxel,
                          const std::vector<std::uint8_t>& on_moving_track) {
  return veto_unconfirmed(points, dynamic, log, static_cast<float>(rule.radius), true, voxel,
                          on_moving_track);
}

std::vector<std::int32_t> seen_standing(const VisibilityMap& log, const Eigen::Matrix3Xf& points,
                                        const std::vector<std::int32_t>& among) {
  std::vector<std::int32_t> out;
  for (const auto i : among) {
    if (log.counts(points.col(i)).stood()) out.push_back(i);
  }
  return out;
}

}  // namespace cleanmap
