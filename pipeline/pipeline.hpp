#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/settings.hpp"
#include "dynamics/scorer_config.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "odometry/odometry_config.hpp"

namespace cleanmap::pipeline {

// What a run does: poses (given, or from odometry) -> scorer -> (map). Online: one streaming
// pass with only the scorer's window in memory; decisions use the past and the window only.
// Offline (mapping only): a first pass scores every scan and casts its rays into the log-wide
// visibility map, spilling each scan to disk; a second pass re-reads them and judges every
// point with what the whole log saw through, before and after.
struct PipelineOptions {
  std::filesystem::path input, out;
  bool odometry = false;  // estimate poses (otherwise the sequence must have them)
  bool mapping = false;   // build the OctoMap and map clouds
  std::string command;
  bool offline = false;   // two passes (needs mapping)
  bool mos_predictions = false;  // also OUT/sequences/XX/predictions (apps/mos_layout.hpp)
  std::string mos_sequence;      // XX; empty: the input folder's name
  // A stream pushed scan by scan (OnlineMapper), not a log read from `input`: no files are
  // written, and each scan's outputs go to `on_scan` instead.
  bool streamed = false;
  // Each scan once final: its labels (label-file codes) and scores, both in input order.
  std::function<void(const ScoredScan&, std::vector<std::uint32_t>, std::vector<float>)> on_scan;
};

// Writes every output into options.out, summary.json last; throws Error on bad input (the
// caller marks the summary incomplete).
void run_pipeline(const PipelineOptions& options, const PipelineConfig& config,
                  nlohmann::json summary);

}  // namespace cleanmap::pipeline
