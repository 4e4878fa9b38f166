#include "mapping/whole_log_vote.hpp"

#include "dynamics/euclidean_clusters.hpp"

namespace cleanmap {
namespace {

// Inside the log, a dynamic object stands only if rays went through its cells in at least one
// scan for every kHitsPerThrough scans that hit them. What left its place is seen through by
// the scans after it (or before it came); a static porous or ragged surface (a fence, a hedge,
// a kerb's edge the rings slide along) is hit in nearly every scan that sees it and let through
// now and then. Inside-the-log dynamic clusters of the normals, through per hit summed over the
// cluster's points' cells (scratch dump of every cluster, the centre in a box or on labelled
// points): movers never below 0.04 on any set (Pandar64: 63 points at 0.04-0.05 and 49 k at
// 0.08-0.1, truck 100 braking beside the sensor; SemanticKITTI and the synthetic street never
// below 0.09), while static clusters spread down to 0 (Pandar64: 18.7 k points in (0, 0.04],
// the synthetic street 91).
constexpr std::size_t kHitsPerThrough = 25;
// (A cell never hit, beyond the visibility map's range, has neither: never gone through.)
bool gone_through_too_rarely(std::size_t through, std::size_t hits) {
  return through == 0 || through * kHitsPerThrough < hits;
}

// Dynamic objects the log saw standing back to static: at a log end those seen through less
// often than hit, inside it those seen through in under one scan per kHitsPerThrough that hit
// them (never, for the most part).
std::size_t veto_unconfirmed(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                             const VisibilityMap& log, float radius, bool log_end) {
  std::vector<std::int32_t> moving;
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    if (dynamic[i]) moving.push_back(static_cast<std::int32_t>(i));
  }
  if (moving.empty()) return 0;
  const Eigen::Matrix3Xf sub = points(Eigen::all, moving);
  std::vector<VisibilityMap::Counts> counts(moving.size());
  for (std::size_t k = 0; k < moving.size(); ++k) counts[k] = log.counts(sub.col(static_cast<Eigen::Index>(k)));
  // Inside the log only clusters with a point seen through too rarely can be vetoed: grown from
  // those alone (most scans have a few, and the clustering of every dynamic point doubled pass 2).
  const std::vector<std::uint8_t> all(moving.size(), 1);
  std::vector<std::uint8_t> seed(moving.size(), 1);
  if (!log_end) {
    bool any = false;
    for (std::size_t k = 0; k < moving.size(); ++k) {
      any |= (seed[k] = gone_through_too_rarely(counts[k].through, counts[k].hits));
    }
    if (!any) return 0;
  }
  const auto id = clusters_from_seeds(sub, all, seed, radius);
  std::vector<std::size_t> hits, crossed;
  for (std::size_t k = 0; k < id.size(); ++k) {
    if (id[k] < 0) continue;
    const auto c = static_cast<std::size_t>(id[k]);
    if (c >= hits.size()) {
      hits.resize(c + 1, 0);
      crossed.resize(c + 1, 0);
    }
    hits[c] += counts[k].hits;
    crossed[c] += log_end ? counts[k].crossed : counts[k].through;  // inside: only rays through count
  }
  std::size_t vetoed = 0;
  for (std::size_t k = 0; k < id.size(); ++k) {
    if (id[k] < 0) continue;
    const auto c = static_cast<std::size_t>(id[k]);
    if (log_end ? crossed[c] < hits[c] : gone_through_too_rarely(crossed[c], hits[c])) {
      dynamic[static_cast<std::size_t>(moving[k])] = 0;
      ++vetoed;
    }
  }
  return vetoed;
}

}  // namespace

WholeLogVerdict judge_with_log(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                               const VisibilityMap& log, const GroundQuery& ground_of, const ObjectRule& rule,
                               bool log_end, double voxel) {
  WholeLogVerdict v;
  v.vetoed = veto_unconfirmed(points, dynamic, log, static_cast<float>(rule.radius), log_end);
  const auto objects = free_space_objects(
      points, ground_of, [&](const Eigen::Matrix3Xf& sub) { return log.moved_through(sub); }, rule, voxel);
  for (std::size_t i = 0; i < dynamic.size(); ++i) {
    v.added += objects[i] && !dynamic[i];
    dynamic[i] |= objects[i];
  }
  return v;
}

}  // namespace cleanmap
