#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dynamics/spatiotemporal_scorer.hpp"

namespace cleanmap::pipeline {

// What the first pass of an offline run knows about one scan, kept on disk until the second
// pass judges it with the whole log's visibility: the world-frame points (and their input
// order), the scorer's and tracker's decisions, and the ground-truth labels when the log has
// them. Per point 12 bytes x y z, 4 intensity, 4 time (when the log has them), 4 score, 1
// decision, 4 input index, 4 label (when the log has labels): 25-33 bytes (1 more at the log's
// two ends: on_moving_track). Stored as byte
// planes through a fast zstd level, a spill takes 15.7 bytes a point on the Pandar64 street
// (100 MB for its 30 scans, 184 MB before), 14.3 on SemanticKITTI 04 and 12.8 on the synthetic
// street (summary.json: spill_bytes). Deleted as pass 2 reads them.
struct SpilledScan {
  ScoredScan scored;
  std::vector<std::uint32_t> labels;  // ground truth, per point; empty when none
};

// Returns the bytes written. Throws Error naming the file when it cannot be written whole.
std::size_t write_spill(const std::filesystem::path& file, const ScoredScan& scored,
                        const std::vector<std::uint32_t>& labels);

// What stops an offline run early when its spills will not fit on their disk: `bytes` spilled
// for `done` scans so far, as much again for each of `left` scans to come, against `available`
// bytes free. Empty when they fit (or nothing is known yet). A run that would fill the disk
// hours later says so after its first scan, in one line naming `dir`.
std::string spill_space_problem(const std::filesystem::path& dir, std::size_t bytes,
                                std::size_t done, std::size_t left, std::uintmax_t available);
// The same against the space free on `dir`'s disk now: throws Error with that line.
void check_spill_space(const std::filesystem::path& dir, std::size_t bytes, std::size_t done,
                       std::size_t left);

// Throws Error naming the file when it is not a complete spill.
SpilledScan read_spill(const std::filesystem::path& file);

}  // namespace cleanmap::pipeline
