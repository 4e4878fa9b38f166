#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/settings.hpp"
#include "dynamics/scorer_config.hpp"
#include "odometry/odometry_config.hpp"

namespace cleanmap::app {

// What one streaming pass does: poses (given, or from odometry) -> scorer -> (map), in one pass
// with only the scorer's window in memory.
struct PipelineOptions {
  std::filesystem::path input, out;
  bool odometry = false;  // estimate poses (otherwise the sequence must have them)
  bool mapping = false;   // build the OctoMap and map clouds
  std::string command;
};

// Writes every output into options.out, summary.json last; throws Error on bad input (the
// caller marks the summary incomplete).
void run_pipeline(const PipelineOptions& options, const PipelineConfig& config,
                  nlohmann::json summary);

}  // namespace cleanmap::app
