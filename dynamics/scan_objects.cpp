#include "dynamics/scan_objects.hpp"

#include <algorithm>
#include <cmath>

#include <tsl/robin_map.h>

#include "geometry/voxel_key.hpp"

namespace cleanmap {
namespace {

std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<std::int32_t> grid_components(const Eigen::Matrix3Xf& points,
                                          const std::vector<std::uint8_t>& include, double cell) {
  const double inv = 1.0 / cell;
  tsl::robin_map<VoxelKey, std::uint32_t, VoxelKeyHash> slot;
  std::vector<VoxelKey> keys;
  std::vector<std::int64_t> cell_of(include.size(), -1);
  for (std::size_t i = 0; i < include.size(); ++i) {
    if (!include[i]) continue;
    const auto k = voxel_of(points.col(static_cast<Eigen::Index>(i)), inv);
    const auto [it, fresh] = slot.try_emplace(k, static_cast<std::uint32_t>(keys.size()));
    if (fresh) keys.push_back(k);
    cell_of[i] = it->second;
  }
  std::vector<std::uint32_t> parent(keys.size());
  for (std::uint32_t c = 0; c < parent.size(); ++c) parent[c] = c;
  for (std::uint32_t c = 0; c < keys.size(); ++c) {
    const VoxelKey k = keys[c];
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          // Each touching pair once: the 13 neighbours after this cell in (x, y, z) order.
          if (dx < 0 || (dx == 0 && (dy < 0 || (dy == 0 && dz <= 0)))) continue;
          const auto it = slot.find({k.x + dx, k.y + dy, k.z + dz});
          if (it == slot.end()) continue;
          const auto a = root(parent, c), b = root(parent, it->second);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
  }
  std::vector<std::int32_t> id(include.size(), -1), number(keys.size(), -1);
  std::int32_t next = 0;
  for (std::size_t i = 0; i < include.size(); ++i) {
    if (cell_of[i] < 0) continue;
    const auto r = root(parent, static_cast<std::uint32_t>(cell_of[i]));
    if (number[r] < 0) number[r] = next++;
    id[i] = number[r];
  }
  return id;
}

ScanObjects describe_objects(const Eigen::Matrix3Xf& points, const std::vector<std::int32_t>& id,
                             const std::vector<std::uint8_t>& dynamic, double max_extent,
                             int min_points, const std::vector<std::int32_t>& owner) {
  std::int32_t clusters = 0;
  for (auto c : id) clusters = std::max(clusters, c + 1);
  const auto k = static_cast<std::size_t>(clusters);
  std::vector<ScanObject> all(k);
  std::vector<Eigen::Vector3f> sum(k, Eigen::Vector3f::Zero());
  std::vector<std::uint32_t> moving(k, 0);
  for (auto& o : all) {
    o.lo.setConstant(INFINITY);
    o.hi.setConstant(-INFINITY);
  }
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] < 0) continue;
    const auto c = static_cast<std::size_t>(id[i]);
    const Eigen::Vector3f p = points.col(static_cast<Eigen::Index>(i));
    all[c].lo = all[c].lo.cwiseMin(p);
    all[c].hi = all[c].hi.cwiseMax(p);
    sum[c] += p;
    ++all[c].points;
    moving[c] += dynamic[i] != 0;
  }
  // Renumber the object-sized clusters 0..m-1.
  ScanObjects out;
  std::vector<std::int32_t> renumber(k, -1);
  for (std::size_t c = 0; c < k; ++c) {
    ScanObject& o = all[c];
    if (static_cast<int>(o.points) < std::max(min_points, 1) || (o.hi - o.lo).head<2>().norm() > max_extent) continue;
    o.centroid = sum[c] / static_cast<float>(o.points);
    o.seen_moving = 2 * moving[c] >= o.points;
    renumber[c] = static_cast<std::int32_t>(out.objects.size());
    out.objects.push_back(o);
  }
  out.of_point.resize(owner.size());
  for (std::size_t q = 0; q < owner.size(); ++q) {
    const auto c = id[static_cast<std::size_t>(owner[q])];
    out.of_point[q] = c < 0 ? -1 : renumber[static_cast<std::size_t>(c)];
  }
  return out;
}

}  // namespace cleanmap
