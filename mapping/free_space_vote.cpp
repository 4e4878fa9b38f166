#include "mapping/free_space_vote.hpp"

#include <algorithm>

#include "dynamics/euclidean_clusters.hpp"
#include "geometry/voxel_downsample.hpp"

namespace cleanmap {

std::vector<std::uint8_t> free_space_objects(const Eigen::Matrix3Xf& points,
                                             const GroundQuery& ground_of,
                                             const FreeSpaceQuery& hits_in_free_space,
                                             const ObjectRule& rule, double voxel) {
  const auto n = static_cast<std::size_t>(points.cols());
  std::vector<std::uint8_t> out(n, 0);
  if (n == 0) return out;
  const auto voxels = voxel_downsample_with_owners(points, voxel);
  const auto& keep = voxels.keep;
  const Eigen::Matrix3Xf sub = points(Eigen::all, keep);
  // Ground is never an object: only the rest asks the map (about half the look-ups).
  auto include = ground_of(sub);
  for (auto& v : include) v = v ? 0 : 1;
  std::vector<std::int32_t> above;
  for (std::size_t k = 0; k < include.size(); ++k) {
    if (include[k]) above.push_back(static_cast<std::int32_t>(k));
  }
  const auto answers = hits_in_free_space(sub(Eigen::all, above));
  std::vector<std::uint8_t> hits(keep.size(), 0);
  for (std::size_t j = 0; j < above.size(); ++j) hits[static_cast<std::size_t>(above[j])] = answers[j];
  if (std::none_of(hits.begin(), hits.end(), [](std::uint8_t h) { return h != 0; })) return out;
  // Votes are counted on the subsample: one per occupied voxel.
  const auto moving = moving_objects(sub, include, hits, {}, rule, [&](const auto& in, const auto& seed, float r) {
    return clusters_from_seeds(sub, in, seed, r);
  });
  // Each full-resolution point takes the answer of its voxel's subsample point.
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = moving[static_cast<std::size_t>(voxels.owner[i])] == ClusterVerdict::kMoving;
  }
  return out;
}

}  // namespace cleanmap
