#pragma once

#include <CLI/CLI.hpp>

#include "apps/cli_fields.hpp"
#include "apps/preset_options.hpp"

namespace cleanmap::app {

// Each subcommand registers its options and its callback on the top-level app.
void register_demo(CLI::App& app);
void register_score(CLI::App& app);
void register_odometry(CLI::App& app);
void register_run(CLI::App& app);
void register_eval(CLI::App& app);
void register_compare(CLI::App& app);
void register_report(CLI::App& app);
void register_config(CLI::App& app);

}  // namespace cleanmap::app
