#include "mapping/whole_log_vote.hpp"

#include "dynamics/euclidean_clusters.hpp"

namespace cleanmap {
namespace {

// Dynamic objects the log saw standing back to static: at a log end those seen through less
// often than hit, inside it those never seen through at all.
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
  // Inside the log only clusters with a point never gone through can be vetoed: grown from those
  // alone (most scans have a few, and the clustering of every dynamic point doubled pass 2).
  const std::vector<std::uint8_t> all(moving.size(), 1);
  std::vector<std::uint8_t> seed(moving.size(), 1);
  if (!log_end) {
    bool any = false;
    for (std::size_t k = 0; k < moving.size(); ++k) any |= (seed[k] = counts[k].through == 0);
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
    if (log_end ? crossed[c] < hits[c] : crossed[c] == 0) {
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
