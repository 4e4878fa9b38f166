#pragma once

#include <CLI/CLI.hpp>

#include "evaluation/object_motion.hpp"

namespace cleanmap::app {

// The box ground truth's options, the same on `eval dynamic` and bench/dynamicmap_layout:
// --speed, --speed-window, --box-margin, --box-speed points|centres, --box-moving scan|track,
// --time-from-azimuth, --pose-reference.
void add_box_truth_options(CLI::App& command, BoxTruthOptions& options);

}  // namespace cleanmap::app
