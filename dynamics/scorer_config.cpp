#include "dynamics/scorer_config.hpp"

#include <cmath>

#include "io/error.hpp"

namespace cleanmap {

void validate(const ScorerConfig& c) {
  auto bad = [](const std::string& what) { throw Error("scorer: " + what); };
  if (c.voxel_size < 0) bad("voxel_size must be >= 0 (0 = relative to the scan's size)");
  if (c.voxel_size == 0 && !(c.voxel_divisor > 0)) bad("voxel_divisor must be positive");
  if (c.window_half < 0) bad("window_half must be >= 0");
  if (!(c.radius > 0)) bad("radius must be positive");
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
  if (c.cell_size < 0) bad("cell_size must be >= 0");
  if (!(c.upsample_radius > 0)) bad("upsample_radius must be positive");
  if (c.ground_aware) validate(c.ground);
  if (c.object_completion || c.tracks.enabled) validate(c.objects, "scorer");
  if (!std::isfinite(c.tracks.max_speed) || !(c.tracks.max_speed >= 0))
    bad("track_max_speed must be >= 0");
}

}  // namespace cleanmap
