#include "dynamics/euclidean_clusters.hpp"

#include <algorithm>
#include <cmath>

#include "io/error.hpp"
#include "geometry/radius_grid.hpp"
#include "geometry/voxel_downsample.hpp"

namespace cleanmap {

std::vector<std::int32_t> clusters_from_seeds(const Eigen::Matrix3Xf& points,
                                              const std::vector<std::uint8_t>& include,
                                              const std::vector<std::uint8_t>& seed, float radius) {
  std::vector<std::int32_t> id(include.size(), -1), members;
  for (std::size_t k = 0; k < include.size(); ++k) {
    if (include[k]) members.push_back(static_cast<std::int32_t>(k));
  }
  const RadiusGrid index(points, members, radius);
  // Members of each cube still without a cluster: a flood fill skips the cubes it has taken
  // whole, whose points it would only find labelled (the same clusters, found in the same
  // order). On walls of 0.1 m points a search meets hundreds of points, nearly all labelled.
  std::vector<std::uint32_t> open(index.cubes());
  for (std::uint32_t c = 0; c < open.size(); ++c) open[c] = index.cube_size(c);
  const auto take = [&](std::uint32_t m, std::int32_t cluster) {
    id[static_cast<std::size_t>(members[m])] = cluster;
    --open[index.cube_of(m)];
  };
  std::int32_t next = 0;
  std::vector<std::int32_t> stack;
  for (std::uint32_t m = 0; m < members.size(); ++m) {
    const auto k = members[m];
    if (!seed[static_cast<std::size_t>(k)] || id[static_cast<std::size_t>(k)] >= 0) continue;
    take(m, next);
    stack.assign(1, k);
    while (!stack.empty()) {
      const auto j = stack.back();
      stack.pop_back();
      index.for_each_within(
          points.col(j), [&](std::uint32_t cube) { return open[cube] == 0; },
          [&](std::uint32_t n, float) {
            const auto q = static_cast<std::size_t>(members[n]);
            if (id[q] < 0) {
              take(n, next);
              stack.push_back(static_cast<std::int32_t>(q));
            }
          });
    }
    ++next;
  }
  return id;
}

std::vector<std::int32_t> clusters_on_voxels(const Eigen::Matrix3Xf& points,
                                             const std::vector<std::uint8_t>& include,
                                             const std::vector<std::uint8_t>& seed, float radius,
                                             double voxel) {
  std::vector<std::int32_t> members;
  for (std::size_t i = 0; i < include.size(); ++i) {
    if (include[i]) members.push_back(static_cast<std::int32_t>(i));
  }
  std::vector<std::int32_t> id(include.size(), -1);
  if (members.empty()) return id;
  const Eigen::Matrix3Xf sub = points(Eigen::all, members);
  const auto voxels = voxel_downsample_with_owners(sub, voxel);
  const auto owner = [&](std::size_t m) { return static_cast<std::size_t>(voxels.owner[m]); };
  std::vector<std::uint8_t> rep_seed(voxels.keep.size(), 0);
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (seed[static_cast<std::size_t>(members[m])]) rep_seed[owner(m)] = 1;
  }
  const auto rep_id = clusters_from_seeds(sub(Eigen::all, voxels.keep),
                                          std::vector<std::uint8_t>(voxels.keep.size(), 1), rep_seed, radius);
  for (std::size_t m = 0; m < members.size(); ++m) id[static_cast<std::size_t>(members[m])] = rep_id[owner(m)];
  return id;
}

void validate(const ObjectRule& r, const std::string& who) {
  auto bad = [&](const std::string& what) { throw Error(who + ": " + what); };
  // A cluster grows through points this close: beyond a few metres one street is one object,
  // and each search costs the radius cubed (issue 45: a radius of 1e308 took 30 s on 6 scans).
  if (!std::isfinite(r.radius) || !(r.radius > 0 && r.radius <= 10)) bad("cluster radius must be in (0, 10] m");
  if (r.min_votes < 1) bad("a cluster needs at least 1 vote");
  if (!(r.min_fraction >= 0 && r.min_fraction <= 1)) bad("cluster vote fraction must be in [0, 1]");
  if (!(r.max_extent > 0 && r.max_extent <= 1000)) bad("cluster max extent must be in (0, 1000] m");
  if (!(r.min_split_radius > 0 && r.min_split_radius <= 10)) bad("cluster min split radius must be in (0, 10] m");
}

std::vector<ClusterVerdict> vote_clusters(const Eigen::Matrix3Xf& points,
                                          const std::vector<std::int32_t>& id,
                                          const std::vector<std::uint8_t>& votes,
                                          const std::vector<std::uint8_t>& counts,
                                          const ObjectRule& rule) {
  std::int32_t clusters = 0;
  for (auto c : id) clusters = std::max(clusters, c + 1);
  const auto k = static_cast<std::size_t>(clusters);
  std::vector<int> counted(k, 0), voted(k, 0);
  std::vector<Eigen::Vector3f> lo(k, Eigen::Vector3f::Constant(INFINITY));
  std::vector<Eigen::Vector3f> hi(k, Eigen::Vector3f::Constant(-INFINITY));
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] < 0) continue;
    const auto c = static_cast<std::size_t>(id[i]);
    const auto p = points.col(static_cast<Eigen::Index>(i));
    lo[c] = lo[c].cwiseMin(p);
    hi[c] = hi[c].cwiseMax(p);
    counted[c] += counts.empty() || counts[i];
    voted[c] += votes[i] != 0;
  }
  std::vector<ClusterVerdict> verdict(k, ClusterVerdict::kNotMoving);
  for (std::size_t c = 0; c < k; ++c) {
    if ((hi[c] - lo[c]).head<2>().norm() > rule.max_extent) {
      verdict[c] = ClusterVerdict::kTooLarge;
    } else if (voted[c] < rule.min_votes) {
      verdict[c] = ClusterVerdict::kFewVotes;
    } else if (voted[c] >= rule.min_fraction * counted[c]) {
      verdict[c] = ClusterVerdict::kMoving;
    }
  }
  return verdict;
}

std::vector<ClusterVerdict> moving_objects(const Eigen::Matrix3Xf& points,
                                         const std::vector<std::uint8_t>& include,
                                         const std::vector<std::uint8_t>& votes,
                                         const std::vector<std::uint8_t>& counts,
                                         const ObjectRule& rule, const ClusterFunction& cluster) {
  std::vector<ClusterVerdict> out(include.size(), ClusterVerdict::kNotMoving);
  std::vector<std::uint8_t> left = include;
  for (double radius = rule.radius;; radius /= 2) {
    const auto id = cluster(left, votes, static_cast<float>(radius));
    const auto verdict = vote_clusters(points, id, votes, counts, rule);
    bool split = false;
    for (std::size_t i = 0; i < id.size(); ++i) {
      if (id[i] < 0) {
        // Split off a too-large cluster without a seed of its own: part of no moving object.
        if (left[i]) out[i] = ClusterVerdict::kNotMoving;
        left[i] = 0;
        continue;
      }
      out[i] = verdict[static_cast<std::size_t>(id[i])];
      left[i] = out[i] == ClusterVerdict::kTooLarge;
      split = split || left[i];
    }
    if (!split || radius / 2 < rule.min_split_radius) break;
  }
  return out;
}

}  // namespace cleanmap
