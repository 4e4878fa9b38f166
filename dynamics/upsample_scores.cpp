#include "dynamics/upsample_scores.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include <tsl/robin_map.h>
#include <tsl/robin_set.h>

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

}  // namespace

PointDecisions upsample_scores(const Eigen::Matrix3Xf& full, const Eigen::Matrix3Xf& down,
                               const std::vector<std::int32_t>& owner, const PointDecisions& d,
                               const std::string& method, double radius,
                               const std::vector<std::uint8_t>& keeps_own) {
  const auto n = static_cast<std::size_t>(full.cols());
  PointDecisions out;
  out.score.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.dynamic.assign(n, 0);
  if (down.cols() == 0) return out;
  if (method == "paper") {
    paper_rule(full, down, owner, d, radius, keeps_own, out);
  } else {
    nearest_rule(full, down, d, radius, out);
  }
  return out;
}

}  // namespace cleanmap
