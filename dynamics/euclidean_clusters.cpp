#include "dynamics/euclidean_clusters.hpp"

#include <algorithm>
#include <cmath>

#include "io/point_index.hpp"

namespace cleanmap {

std::vector<std::int32_t> clusters_from_seeds(const Eigen::Matrix3Xf& points,
                                              const std::vector<std::uint8_t>& include,
                                              const std::vector<std::uint8_t>& seed, float radius) {
  std::vector<std::int32_t> id(include.size(), -1), members;
  for (std::size_t k = 0; k < include.size(); ++k) {
    if (include[k]) members.push_back(static_cast<std::int32_t>(k));
  }
  const Eigen::Matrix3Xf subset = points(Eigen::all, members);
  const PointIndex index(subset);
  std::int32_t next = 0;
  std::vector<std::int32_t> stack;
  for (const auto k : members) {
    if (!seed[static_cast<std::size_t>(k)] || id[static_cast<std::size_t>(k)] >= 0) continue;
    id[static_cast<std::size_t>(k)] = next;
    stack.assign(1, k);
    while (!stack.empty()) {
      const auto j = stack.back();
      stack.pop_back();
      index.for_each_within(points.col(j), radius, [&](std::uint32_t m, float) {
        const auto q = static_cast<std::size_t>(members[m]);
        if (id[q] < 0) {
          id[q] = next;
          stack.push_back(static_cast<std::int32_t>(q));
        }
      });
    }
    ++next;
  }
  return id;
}

std::vector<std::uint8_t> vote_clusters(const Eigen::Matrix3Xf& points,
                                        const std::vector<std::int32_t>& id,
                                        const std::vector<std::uint8_t>& votes,
                                        const std::vector<std::uint8_t>& counts, int min_votes,
                                        double min_fraction, double max_extent) {
  std::int32_t clusters = 0;
  for (auto c : id) clusters = std::max(clusters, c + 1);
  std::vector<int> counted(static_cast<std::size_t>(clusters), 0), voted(static_cast<std::size_t>(clusters), 0);
  std::vector<Eigen::Vector3f> lo(static_cast<std::size_t>(clusters), Eigen::Vector3f::Constant(INFINITY));
  std::vector<Eigen::Vector3f> hi(static_cast<std::size_t>(clusters), Eigen::Vector3f::Constant(-INFINITY));
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] < 0) continue;
    const auto c = static_cast<std::size_t>(id[i]);
    const auto p = points.col(static_cast<Eigen::Index>(i));
    lo[c] = lo[c].cwiseMin(p);
    hi[c] = hi[c].cwiseMax(p);
    counted[c] += counts.empty() || counts[i];
    voted[c] += votes[i] != 0;
  }
  std::vector<std::uint8_t> moving(static_cast<std::size_t>(clusters), 0);
  for (std::size_t c = 0; c < moving.size(); ++c) {
    moving[c] = voted[c] >= min_votes && voted[c] >= min_fraction * counted[c] &&
                (hi[c] - lo[c]).head<2>().norm() <= max_extent;
  }
  return moving;
}

}  // namespace cleanmap
