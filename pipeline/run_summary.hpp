#pragma once

#include <nlohmann/json.hpp>

#include "evaluation/dynamic_metrics.hpp"

namespace cleanmap::pipeline {

// summary.json's moving-class block: IoU, precision, recall and the counts behind them.
nlohmann::json metrics_json(const MovingConfusion& c);

// The versions of the libraries this binary was built with.
nlohmann::json library_versions();

}  // namespace cleanmap::pipeline
