#include "mapping/free_space_vote.hpp"

#include <tbb/parallel_for.h>

#include "dynamics/euclidean_clusters.hpp"
#include <tsl/robin_map.h>

#include "io/voxel_key.hpp"
#include "io/voxel_downsample.hpp"

namespace cleanmap {

std::vector<std::uint8_t> free_space_objects(const Eigen::Matrix3Xf& points,
                                             const std::vector<std::uint8_t>& ground,
                                             const FreeSpaceQuery& hits_in_free_space,
                                             double fraction, int min_hits, float cluster_radius,
                                             double max_extent) {
  const auto n = static_cast<std::size_t>(points.cols());
  std::vector<std::uint8_t> out(n, 0);
  if (n == 0) return out;
  constexpr double kVoxel = 0.2;
  const auto keep = voxel_downsample(points, kVoxel);
  Eigen::Matrix3Xf sub(3, static_cast<Eigen::Index>(keep.size()));
  std::vector<std::uint8_t> include(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    sub.col(static_cast<Eigen::Index>(k)) = points.col(keep[k]);
    include[k] = ground[static_cast<std::size_t>(keep[k])] ? 0 : 1;
  }
  const auto cluster = euclidean_clusters(sub, include, cluster_radius);
  const auto hits = hits_in_free_space(sub);
  // Each full-resolution point belongs to the cluster of its voxel's representative.
  const double inv = 1.0 / kVoxel;
  tsl::robin_map<VoxelKey, std::int32_t, VoxelKeyHash> representative;
  representative.reserve(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    representative[voxel_of(points.col(keep[k]), inv)] = static_cast<std::int32_t>(k);
  }
  std::vector<std::int32_t> owner(n, -1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (ground[i]) continue;
      const auto it = representative.find(voxel_of(points.col(static_cast<Eigen::Index>(i)), inv));
      if (it != representative.end()) owner[i] = cluster[static_cast<std::size_t>(it->second)];
    }
  });
  std::int32_t clusters = 0;
  for (auto c : cluster) clusters = std::max(clusters, c + 1);
  // Votes are counted on the subsample: one per occupied 0.2 m voxel.
  std::vector<int> size(clusters, 0), hit(clusters, 0);
  std::vector<Eigen::Vector3f> lo(clusters, Eigen::Vector3f::Constant(INFINITY));
  std::vector<Eigen::Vector3f> hi(clusters, Eigen::Vector3f::Constant(-INFINITY));
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const auto c = cluster[k];
    if (c < 0) continue;
    ++size[c];
    hit[c] += hits[k];
    lo[c] = lo[c].cwiseMin(sub.col(static_cast<Eigen::Index>(k)));
    hi[c] = hi[c].cwiseMax(sub.col(static_cast<Eigen::Index>(k)));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = owner[i];
    out[i] = c >= 0 && hit[c] >= min_hits && hit[c] >= fraction * size[c] &&
             (hi[c] - lo[c]).head<2>().norm() <= max_extent;
  }
  return out;
}

}  // namespace cleanmap
