#include "dynamics/scorer_config.hpp"

#include <cmath>

#include "io/error.hpp"

namespace cleanmap {
namespace {
constexpr double kMinLength = 1e-3, kMaxLength = 100.0;
constexpr int kMaxWindowHalf = 1000;
}  // namespace

void validate(const ScorerConfig& c) {
  auto bad = [](const std::string& what) { throw Error("scorer: " + what); };
  // Lengths become integer cell keys (int32) of coordinates up to 1e6 m from the map's origin,
  // and a cell size sets how many cells a query looks up: the ranges below are what that code
  // can hold (issue 45: --radius 1e-10 overflowed the keys and crashed, a tiny --cell-size
  // asked for 10^17 neighbour cells and hung).
  if (!(c.voxel_size == 0 || (c.voxel_size >= kMinLength && c.voxel_size <= kMaxLength))) {
    bad("voxel_size must be 0 (relative to the scan's size) or in [0.001, 100] m");
  }
  if (c.voxel_size == 0 && !(c.voxel_divisor > 0 && c.voxel_divisor <= 1e5)) bad("voxel_divisor must be in (0, 1e5]");
  // The window holds 2N+1 scans in memory (about 10 MB each at 100k downsampled points): a
  // thousand is 20 GB (issue 45: --window-half 1073741823 hung).
  if (c.window_half < 0 || c.window_half > kMaxWindowHalf) bad("window_half must be in [0, 1000]");
  if (!(c.radius >= kMinLength && c.radius <= kMaxLength)) bad("radius must be in [0.001, 100] m");
  if (!std::isfinite(c.pose_noise) || c.pose_noise < 0) bad("pose_noise must be >= 0 (metres)");
  if (!std::isfinite(c.pose_noise_deg) || c.pose_noise_deg < 0) bad("pose_noise_deg must be >= 0");
  if (!(c.time_scale > 0)) bad("time_scale must be positive");
  if (c.max_eigen_ratio < 0 || c.max_eigen_ratio > 1) bad("max_eigen_ratio must be in [0, 1]");
  if (c.min_neighbors < 4) bad("min_neighbors must be at least 4 (a 4D PCA needs them)");
  if (c.mode != "fast" && c.mode != "exact")
    bad("mode must be 'fast' or 'exact', not '" + c.mode + "'");
  if (c.upsample != "nearest" && c.upsample != "paper") {
    bad("upsample must be 'nearest' or 'paper', not '" + c.upsample + "'");
  }
  // A query looks up (2k + 1)^3 cells, k = ceil(radius / cell_size): at most 729.
  if (!(c.cell_size == 0 || (c.cell_size >= c.radius / 4 && c.cell_size <= kMaxLength))) {
    bad("cell_size must be 0 (= radius) or in [radius / 4, 100] m: a query looks up (2 ceil(radius / cell_size) + 1)^3 cells");
  }
  if (!(c.upsample_radius >= kMinLength && c.upsample_radius <= kMaxLength)) bad("upsample_radius must be in [0.001, 100] m");
  if (c.ground_aware) validate(c.ground);
  if (c.object_completion || c.tracks.enabled) validate(c.objects, "scorer");
  if (!std::isfinite(c.tracks.max_speed) || !(c.tracks.max_speed >= 0))
    bad("track_max_speed must be >= 0");
}

}  // namespace cleanmap
