#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/trajectory_metrics.hpp"
#include "io/pose_file.hpp"

namespace cleanmap::pipeline {

// Creates the output folder (and subfolders), failing with a clear message when it cannot.
void make_dirs(const std::filesystem::path& dir);

// Removes a file or a folder (with its contents) when the scope ends, however it ends: the
// report's data file, the offline pass's spills. An empty path removes nothing.
struct RemovedAtExit {
  std::filesystem::path path;
  explicit RemovedAtExit(std::filesystem::path p) : path(std::move(p)) {}
  RemovedAtExit(const RemovedAtExit&) = delete;
  RemovedAtExit& operator=(const RemovedAtExit&) = delete;
  ~RemovedAtExit() {
    std::error_code ignored;
    if (!path.empty()) std::filesystem::remove_all(path, ignored);
  }
};

// The key every cleanmap summary.json carries (value: the output format, 1): only a folder with
// it is an earlier cleanmap output that --overwrite may empty. A "command" key alone had been
// the rule, and another tool's summary.json cost a user's thesis.tex (issue 45).
inline constexpr const char* kOutputMarker = "cleanmap_output";

// Writes OUT/summary.json atomically (temporary file, then rename): a reader never sees half a
// summary, and "complete": true appears only once everything else is written.
void write_summary(const std::filesystem::path& out, nlohmann::json summary, bool complete,
                   const std::string& error = "");

// A number for JSON; NaN (a metric with nothing to measure) becomes null.
nlohmann::json json_number(double v);

// KITTI segment errors per length and pooled, as every command reports them.
nlohmann::json kitti_json(const KittiErrors& kitti);

// OUT/poses_kitti.txt and OUT/poses_tum.txt (real stamps) in the ground truth's frame (camera-0
// when a KITTI Tr is known, else lidar), OUT/poses.txt + OUT/times.txt in the lidar frame (OUT
// then reads as a sequence).
void write_pose_files(const std::filesystem::path& out, const std::vector<StampedPose>& poses,
                      const std::optional<Eigen::Isometry3d>& kitti_tr);

// What summary.json says of those files: frame and time of each.
nlohmann::json pose_files_json(const std::optional<Eigen::Isometry3d>& kitti_tr, double reference_offset);

}  // namespace cleanmap::pipeline
