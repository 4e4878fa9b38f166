#include "odometry/voxel_hash_map.hpp"

#include <algorithm>
#include <cmath>

namespace cleanmap {

std::size_t VoxelHashMap::point_count() const {
  std::size_t n = 0;
  for (const auto& [key, pts] : voxels) n += pts.size();
  return n;
}

double VoxelHashMap::min_spacing() const {
  return voxel_size / std::sqrt(static_cast<double>(max_points));
}

void VoxelHashMap::add(const std::vector<Eigen::Vector3d>& points) {
  const double inv = 1.0 / voxel_size, spacing_sq = min_spacing() * min_spacing();
  for (const auto& p : points) {
    auto& v = voxels[voxel_of(p, inv)];
    if (static_cast<int>(v.size()) >= max_points) continue;
    const bool known = std::any_of(v.begin(), v.end(), [&](const Eigen::Vector3d& m) {
      return (m - p).squaredNorm() < spacing_sq;
    });
    if (!known) v.push_back(p);
  }
}

void VoxelHashMap::remove_far(const Eigen::Vector3d& origin) {
  const double max_sq = max_distance * max_distance;
  for (auto it = voxels.begin(); it != voxels.end();) {
    if (!it->second.empty() && (it->second.front() - origin).squaredNorm() > max_sq) {
      it = voxels.erase(it);
    } else {
      ++it;
    }
  }
}

std::size_t VoxelHashMap::remove_near(const std::vector<Eigen::Vector3d>& points, double radius) {
  const double inv = 1.0 / voxel_size, r_sq = radius * radius;
  std::size_t removed = 0;
  for (const auto& p : points) {
    auto it = voxels.find(voxel_of(p, inv));
    if (it == voxels.end()) continue;
    auto& v = it.value();
    const auto before = v.size();
    v.erase(std::remove_if(v.begin(), v.end(), [&](const Eigen::Vector3d& m) { return (m - p).squaredNorm() < r_sq; }),
            v.end());
    removed += before - v.size();
    if (v.empty()) voxels.erase(it);
  }
  return removed;
}

// The centre voxel first, then each neighbour only when its box lies nearer than the k-th best
// so far (or max_dist): the centre usually holds the k nearest, and the 26 hash look-ups it
// saves were most of the odometry's time. Exact: a skipped box holds no nearer point.
void VoxelHashMap::nearest(const Eigen::Vector3d& q, int k, double max_dist,
                           std::vector<Eigen::Vector3d>& out) const {
  out.clear();
  const double inv = 1.0 / voxel_size;
  const VoxelKey c = voxel_of(q, inv);
  // Distance from q to the lower and upper face of its voxel, per axis.
  const Eigen::Vector3d low = q - Eigen::Vector3d(c.x, c.y, c.z) * voxel_size;
  const Eigen::Vector3d high = Eigen::Vector3d::Constant(voxel_size) - low;
  // (squared distance, point) of the k best as a max-heap: k is small.
  thread_local std::vector<std::pair<double, const Eigen::Vector3d*>> best;
  best.clear();
  const double max_sq = max_dist * max_dist;
  auto visit = [&](const VoxelKey& key) {
    const auto it = voxels.find(key);
    if (it == voxels.end()) return;
    for (const auto& p : it->second) {
      const double d = (p - q).squaredNorm();
      if (d > max_sq) continue;
      if (static_cast<int>(best.size()) < k) {
        best.emplace_back(d, &p);
        std::push_heap(best.begin(), best.end());
      } else if (d < best.front().first) {
        std::pop_heap(best.begin(), best.end());
        best.back() = {d, &p};
        std::push_heap(best.begin(), best.end());
      }
    }
  };
  auto gap = [&](int o, int axis) { return o < 0 ? low[axis] : (o > 0 ? high[axis] : 0.0); };
  visit(c);
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        const double gx = gap(x, 0), gy = gap(y, 1), gz = gap(z, 2);
        const double bound = static_cast<int>(best.size()) < k ? max_sq : best.front().first;
        if (gx * gx + gy * gy + gz * gz > bound) continue;
        visit({c.x + x, c.y + y, c.z + z});
      }
    }
  }
  for (const auto& [d, p] : best) out.push_back(*p);
}

}  // namespace cleanmap
