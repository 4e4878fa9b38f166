#include "apps/commands.hpp"
#include "apps/output_claim.hpp"
#include "apps/output_dir.hpp"
#include "apps/pipeline.hpp"

namespace cleanmap::app {
namespace fs = std::filesystem;

void register_score(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-score", config;
    bool overwrite = false;
    PresetOptions options;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("score", "Score every point of a registered sequence as dynamic "
                                          "or static (spatiotemporal normals)");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  add_output_options(*cmd, args->out, args->overwrite, "Output folder");
  cmd->add_option("--config", args->config, "YAML preset (sections 'input', 'scorer')");
  args->options.add_to(*cmd, PresetOptions::kScorer);
  cmd->callback([cmd, args] {
    run_guarded({args->out, "score", args->options.input_files(args->input, args->config), args->overwrite}, [&] {
      run_pipeline({args->input, args->out, false, false, "score"}, args->options.resolve(*cmd, args->config), {});
    });
  });
}

void register_run(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-run", config;
    bool overwrite = false;
    bool use_given_poses = false;
    bool online = false;
    PresetOptions options;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("run", "Raw log in, clean static map out: odometry (or given "
                                        "poses), dynamic scoring, OctoMap mapping, exports");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  add_output_options(*cmd, args->out, args->overwrite, "Output folder");
  cmd->add_option("--config", args->config, "YAML preset (sections input, odometry, scorer, mapping)");
  cmd->add_flag("--use-given-poses", args->use_given_poses,
                "Take poses from --poses or the sequence's poses.txt instead of running odometry");
  cmd->add_flag("--online", args->online,
                "One streaming pass, as for a live sensor: decisions see the past and the scorer's window "
                "only (default: two passes, the whole log's visibility judges every scan)");
  args->options.add_to(*cmd, PresetOptions::kOdometry | PresetOptions::kScorer | PresetOptions::kMapping);
  cmd->callback([cmd, args] {
    run_guarded({args->out, "run", args->options.input_files(args->input, args->config), args->overwrite}, [&] {
      const PipelineConfig cfg = args->options.resolve(*cmd, args->config);
      // An explicit --poses file means "use these poses" too.
      const bool given = args->use_given_poses || !cfg.input.poses.empty();
      run_pipeline({args->input, args->out, !given, true, "run", !args->online}, cfg, {});
    });
  });
}

}  // namespace cleanmap::app
