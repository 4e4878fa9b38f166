#include "dynamics/euclidean_clusters.hpp"

#include <numeric>

#include "io/point_index.hpp"

namespace cleanmap {
namespace {

std::int32_t find_root(std::vector<std::int32_t>& parent, std::int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

std::vector<std::int32_t> euclidean_clusters(const Eigen::Matrix3Xf& points,
                                             const std::vector<std::uint8_t>& include,
                                             float radius) {
  std::vector<std::int32_t> members;
  for (std::size_t i = 0; i < include.size(); ++i) {
    if (include[i]) members.push_back(static_cast<std::int32_t>(i));
  }
  Eigen::Matrix3Xf subset(3, static_cast<Eigen::Index>(members.size()));
  for (std::size_t k = 0; k < members.size(); ++k) subset.col(static_cast<Eigen::Index>(k)) = points.col(members[k]);
  const PointIndex index(subset);
  std::vector<std::int32_t> parent(members.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t k = 0; k < members.size(); ++k) {
    index.for_each_within(subset.col(static_cast<Eigen::Index>(k)), radius, [&](std::uint32_t j, float) {
      const auto a = find_root(parent, static_cast<std::int32_t>(k));
      const auto b = find_root(parent, static_cast<std::int32_t>(j));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    });
  }
  std::vector<std::int32_t> id(include.size(), -1);
  std::vector<std::int32_t> root_id(members.size(), -1);
  std::int32_t next = 0;
  for (std::size_t k = 0; k < members.size(); ++k) {
    const auto r = find_root(parent, static_cast<std::int32_t>(k));
    if (root_id[r] < 0) root_id[r] = next++;
    id[members[k]] = root_id[r];
  }
  return id;
}

}  // namespace cleanmap
