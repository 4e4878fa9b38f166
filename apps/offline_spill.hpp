#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "dynamics/spatiotemporal_scorer.hpp"

namespace cleanmap::app {

// What the first pass of an offline run knows about one scan, kept on disk until the second
// pass judges it with the whole log's visibility: the world-frame points (and their input
// order), the scorer's and tracker's decisions, and the ground-truth labels when the log has
// them. About 29 bytes per point (12 xyz, 4 intensity, 4 score, 1 decision, 4 input index,
// 4 label): 185 MB for the 30-scan Pandar64 street, deleted when the run ends.
struct SpilledScan {
  ScoredScan scored;
  std::vector<std::uint32_t> labels;  // ground truth, per point; empty when none
};

void write_spill(const std::filesystem::path& file, const ScoredScan& scored,
                 const std::vector<std::uint32_t>& labels);

// Throws Error naming the file when it is not a complete spill.
SpilledScan read_spill(const std::filesystem::path& file);

}  // namespace cleanmap::app
