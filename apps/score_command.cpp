#include "apps/commands.hpp"
#include "apps/output_dir.hpp"
#include "apps/pipeline.hpp"

namespace cleanmap::app {
namespace fs = std::filesystem;

void register_score(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-score", config;
    InputSettings input_cli;
    ScorerConfig scorer_cli;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("score", "Score every point of a registered sequence as dynamic "
                                          "or static (spatiotemporal normals)");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
  cmd->add_option("--config", args->config, "YAML preset (sections 'input', 'scorer')");
  add_options(*cmd, args->input_cli, input_fields());
  add_options(*cmd, args->scorer_cli, scorer_fields());
  cmd->callback([cmd, args] {
    run_guarded(args->out, "score", [&] {
      const auto preset = load_optional_preset(args->config);
      PipelineConfig cfg;
      cfg.input = resolve(*cmd, preset, args->config, "input", InputSettings{}, args->input_cli, input_fields());
      cfg.scorer = resolve(*cmd, preset, args->config, "scorer", ScorerConfig{}, args->scorer_cli, scorer_fields());
      run_pipeline({args->input, args->out, false, false, "score"}, cfg, {});
    });
  });
}

void register_run(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-run", config;
    bool use_given_poses = false;
    InputSettings input_cli;
    OdometryConfig odometry_cli;
    ScorerConfig scorer_cli;
    MappingSettings mapping_cli;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Raw log in, clean static map out: odometry (or given "
                                        "poses), dynamic scoring, OctoMap mapping, exports");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
  cmd->add_option("--config", args->config, "YAML preset (sections input, odometry, scorer, mapping)");
  cmd->add_flag("--use-given-poses", args->use_given_poses,
                "Take poses from --poses or the sequence's poses.txt instead of running odometry");
  add_options(*cmd, args->input_cli, input_fields());
  add_options(*cmd, args->odometry_cli, odometry_fields());
  add_options(*cmd, args->scorer_cli, scorer_fields());
  add_options(*cmd, args->mapping_cli, mapping_fields());
  cmd->callback([cmd, args] {
    run_guarded(args->out, "run", [&] {
      const auto preset = load_optional_preset(args->config);
      PipelineConfig cfg;
      cfg.input = resolve(*cmd, preset, args->config, "input", InputSettings{}, args->input_cli, input_fields());
      cfg.odometry = resolve(*cmd, preset, args->config, "odometry", OdometryConfig{}, args->odometry_cli, odometry_fields());
      cfg.scorer = resolve(*cmd, preset, args->config, "scorer", ScorerConfig{}, args->scorer_cli, scorer_fields());
      cfg.mapping = resolve(*cmd, preset, args->config, "mapping", MappingSettings{}, args->mapping_cli, mapping_fields());
      // An explicit --poses file means "use these poses" too.
      const bool given = args->use_given_poses || !cfg.input.poses.empty();
      run_pipeline({args->input, args->out, !given, true, "run"}, cfg, {});
    });
  });
}

}  // namespace cleanmap::app
