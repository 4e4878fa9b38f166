#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/settings.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "io/pose_file.hpp"
#include "mapping/visibility_map.hpp"

namespace cleanmap::pipeline {

struct OfflinePassStats {
  std::size_t added = 0;   // points the whole log's visibility made dynamic
  std::size_t vetoed = 0;  // points it made static again (log ends)
  double rays_seconds = 0, judging_seconds = 0;
};

// The second half of an offline run, once pass 1 has counted every scan's hits into
// `visibility` and spilled scans 0..scans-1 to `spill_dir` (NNNNNN.spill): every scan's rays
// (from where the sensor was at each point's time, by `poses`, one per scan; any other count:
// from each scan's pose),
// then every scan, in order, judged with the whole log (judge_with_log, its ground resting on
// the log's `floor` as well; scans side by side, as the map is read-only by then), handed to
// `map_scan` (with where its sensor was, as its rays) and `write_scan` in order. Progress on the
// terminal per sweep; the spills are deleted as the last sweep reads them (the caller owns the
// folder, and removes it however the run ends).
OfflinePassStats run_offline_pass(
    const std::string& command, std::size_t scans, const std::filesystem::path& spill_dir,
    VisibilityMap& visibility, const LogFloor& floor, const std::vector<StampedPose>& poses,
    const PipelineConfig& cfg,
    const std::function<void(ScoredScan&, const std::optional<SweepOrigin>&)>& map_scan,
    const std::function<void(ScoredScan&, const std::vector<std::uint32_t>&)>& write_scan);

}  // namespace cleanmap::pipeline
