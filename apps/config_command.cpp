// `cleanmap config`: the effective settings (built-in defaults, then --config, then options)
// as a YAML preset on stdout, which --config accepts back.
#include <cstdio>

#include "apps/commands.hpp"
#include "pipeline/preset_yaml.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;

void register_config(CLI::App& app) {
  struct Args {
    std::filesystem::path config;
    PresetOptions options;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("config", "Print the effective settings (defaults, --config, options) as a YAML "
                                           "preset that --config reads back");
  cmd->add_option("--config", args->config, "YAML preset to start from");
  const int all = PresetOptions::kOdometry | PresetOptions::kScorer | PresetOptions::kMapping;
  args->options.add_to(*cmd, all);
  cmd->callback([cmd, args, all] {
    std::fputs(preset_yaml(args->options.resolve(*cmd, args->config), all).c_str(), stdout);
  });
}

}  // namespace cleanmap::app
