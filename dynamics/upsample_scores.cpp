#include "dynamics/upsample_scores.hpp"

#include <tbb/parallel_for.h>
#include <tsl/robin_map.h>
#include <tsl/robin_set.h>

#include <array>
#include <atomic>
#include <climits>
#include <cmath>
#include <limits>

#include "geometry/point_index.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {
namespace {

void nearest_rule(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down, const PointDecisions& d,
                  double radius, PointDecisions& out) {
  const PointIndex all(down);
  const float r_sq = static_cast<float>(radius * radius);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.score.size(), 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const auto nn = all.nearest(full.col(static_cast<Eigen::Index>(i)));
      if (nn && nn->second <= r_sq) {
        out.score[i] = d.score[nn->first];
        out.dynamic[i] = d.dynamic[nn->first];
      }
    }
  });
}

// The paper's rule. Dynamic points are few: bin them in cells of the radius, and mark every
// cell next to one, so that almost every full-resolution point is settled by one look-up.
void paper_rule(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                const std::vector<std::int32_t>& owner, const PointDecisions& d, double radius,
                const std::vector<std::uint8_t>& keeps_own, PointDecisions& out) {
  const double inv = 1.0 / radius;
  const float r_sq = static_cast<float>(radius * radius);
  tsl::robin_map<VoxelKey, std::vector<std::int32_t>, VoxelKeyHash> dynamic_cells;
  for (std::size_t k = 0; k < d.dynamic.size(); ++k) {
    if (d.dynamic[k]) dynamic_cells[voxel_of(down.col(static_cast<Eigen::Index>(k)), inv)].push_back(static_cast<std::int32_t>(k));
  }
  tsl::robin_set<VoxelKey, VoxelKeyHash> near;
  for (const auto& [c, members] : dynamic_cells) {
    for (int x = -1; x <= 1; ++x) {
      for (int y = -1; y <= 1; ++y) {
        for (int z = -1; z <= 1; ++z) near.insert({c.x + x, c.y + y, c.z + z});
      }
    }
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.score.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const auto own = static_cast<std::size_t>(owner[i]);
      out.score[i] = d.score[own];
      if (!keeps_own.empty() && keeps_own[own]) {
        out.dynamic[i] = d.dynamic[own];
        continue;
      }
      if (near.empty()) continue;
      const auto p = full.col(static_cast<Eigen::Index>(i));
      const VoxelKey c = voxel_of(p, inv);
      if (!near.count(c)) continue;
      bool hit = false;
      for (int x = -1; x <= 1 && !hit; ++x) {
        for (int y = -1; y <= 1 && !hit; ++y) {
          for (int z = -1; z <= 1 && !hit; ++z) {
            const auto it = dynamic_cells.find({c.x + x, c.y + y, c.z + z});
            if (it == dynamic_cells.end()) continue;
            for (const auto k : it->second) {
              if ((down.col(k) - p).squaredNorm() <= r_sq) {
                hit = true;
                break;
              }
            }
          }
        }
      }
      out.dynamic[i] = hit ? 1 : 0;
    }
  });
}

void nearest_by_grid(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                     const std::vector<std::int32_t>& owner, const PointDecisions& d, double radius,
                     double voxel, PointDecisions& out) {
  const auto nn = nearest_on_voxels(full, down, owner, voxel);
  const float r_sq = static_cast<float>(radius * radius);
  for (std::size_t i = 0; i < nn.size(); ++i) {
    const auto k = static_cast<std::size_t>(nn[i]);
    if ((down.col(nn[i]) - full.col(static_cast<Eigen::Index>(i))).squaredNorm() > r_sq) continue;
    out.score[i] = d.score[k];
    out.dynamic[i] = d.dynamic[k];
  }
}

}  // namespace

std::vector<std::int32_t> nearest_on_voxels(const Eigen::Matrix3Xf& full,
                                            const Eigen::Matrix3Xf& down,
                                            const std::vector<std::int32_t>& owner, double voxel) {
  const double inv = 1.0 / voxel;
  tsl::robin_map<VoxelKey, std::int32_t, VoxelKeyHash> at;
  at.reserve(static_cast<std::size_t>(down.cols()));
  for (Eigen::Index k = 0; k < down.cols(); ++k)
    at.emplace(voxel_of(down.col(k), inv), static_cast<std::int32_t>(k));
  std::vector<std::int32_t> nn(owner);
  static std::atomic<std::uint64_t> calls{0};
  const std::uint64_t call = ++calls;  // names this table in the threads' caches
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nn.size(), 1024), [&](const auto& range) {
    // Points come in firing order, so a point's neighbouring voxels were most often asked for
    // a few points before: those answers (-1: no downsampled point there), direct-mapped into
    // 64 kB, come before the table, whose look-ups miss the cache.
    constexpr int kBits = 12;
    thread_local std::vector<std::pair<VoxelKey, std::int32_t>> recent;
    thread_local std::uint64_t recent_call = 0;
    if (recent_call != call) {  // a new table: forget the last one's answers
      recent.assign(std::size_t{1} << kBits, {VoxelKey{INT32_MIN, INT32_MIN, INT32_MIN}, -1});
      recent_call = call;
    }
    const auto lookup = [&](const VoxelKey& key) {
      auto& r = recent[(packed_key(key) * 0x9E3779B97F4A7C15ull) >> (64 - kBits)];
      if (!(r.first == key)) {
        const auto it = at.find(key);
        r = {key, it == at.end() ? -1 : it->second};
      }
      return r.second;
    };
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f p = full.col(static_cast<Eigen::Index>(i));
      float best = (down.col(nn[i]) - p).squaredNorm();
      if (best == 0.0f) continue;  // the point stands for its voxel itself
      const VoxelKey c = voxel_of(p, inv);
      const Eigen::Vector3d frac = p.cast<double>() * inv - Eigen::Vector3d(c.x, c.y, c.z);
      // A voxel is skipped only when its box is clearly farther than the best so far (in
      // voxels, with a margin for the float distance's rounding). Per axis, the squared gap
      // to the voxels -2..2 away; the offsets within the limit on each axis span a small box.
      const double limit = static_cast<double>(best) * inv * inv * (1.0 + 1e-5) + 1e-12;
      std::array<std::array<double, 5>, 3> gap{};
      std::array<int, 3> lo{}, hi{};
      for (int a = 0; a < 3; ++a) {
        for (int o = -2; o <= 2; ++o) {
          const double g = o > 0 ? o - frac[a] : o < 0 ? -o - 1.0 + frac[a] : 0.0;
          gap[a][o + 2] = g > 0 ? g * g : 0.0;
        }
        lo[a] = gap[a][0] <= limit ? -2 : gap[a][1] <= limit ? -1 : 0;
        hi[a] = gap[a][4] <= limit ? 2 : gap[a][3] <= limit ? 1 : 0;
      }
      for (int x = lo[0]; x <= hi[0]; ++x) {
        for (int y = lo[1]; y <= hi[1]; ++y) {
          for (int z = lo[2]; z <= hi[2]; ++z) {
            if ((x == 0 && y == 0 && z == 0) ||
                gap[0][x + 2] + gap[1][y + 2] + gap[2][z + 2] > limit)
              continue;
            const std::int32_t k = lookup({c.x + x, c.y + y, c.z + z});
            if (k < 0) continue;
            const float dist = (down.col(k) - p).squaredNorm();
            if (dist < best || (dist == best && k < nn[i])) {
              best = dist;
              nn[i] = k;
            }
          }
        }
      }
    }
  });
  return nn;
}

PointDecisions upsample_scores(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                               const std::vector<std::int32_t>& owner, const PointDecisions& d,
                               const std::string& method, double radius,
                               const std::vector<std::uint8_t>& keeps_own, double voxel_size) {
  const auto n = static_cast<std::size_t>(full.cols());
  PointDecisions out;
  out.score.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.dynamic.assign(n, 0);
  if (down.cols() == 0) return out;
  if (method == "paper") {
    paper_rule(full, down, owner, d, radius, keeps_own, out);
  } else if (voxel_size > 0 && owner.size() == n) {
    nearest_by_grid(full, down, owner, d, radius, voxel_size, out);
  } else {
    nearest_rule(full, down, d, radius, out);
  }
  return out;
}

}  // namespace cleanmap
