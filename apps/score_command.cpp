#include "apps/commands.hpp"
#include "pipeline/output_claim.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/pipeline.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

struct MosOptions {
  bool enabled = false;
  std::string sequence;
};

void add_mos_options(CLI::App& cmd, MosOptions& mos) {
  cmd.add_flag("--mos-predictions", mos.enabled,
               "Also write OUT/sequences/XX/predictions/NNNNNN.label (SemanticKITTI MOS benchmark layout: 251 "
               "moving, 9 static, one per input point) to zip and submit as it is");
  cmd.add_option("--mos-sequence", mos.sequence, "XX for --mos-predictions (default: the input folder's name, e.g. 08)");
}

}  // namespace

void register_score(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-score", config;
    bool overwrite = false;
    MosOptions mos;
    PresetOptions options;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("score", "Score every point of a registered sequence as dynamic "
                                          "or static (spatiotemporal normals)");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  add_output_options(*cmd, args->out, args->overwrite, "Output folder");
  cmd->add_option("--config", args->config, "YAML preset (sections 'input', 'scorer')");
  add_mos_options(*cmd, args->mos);
  args->options.add_to(*cmd, PresetOptions::kScorer);
  cmd->callback([cmd, args] {
    run_guarded({args->out, "score", args->options.input_files(args->input, args->config), args->overwrite}, [&] {
      PipelineOptions score;
      score.input = args->input;
      score.out = args->out;
      score.command = "score";
      score.mos_predictions = args->mos.enabled;
      score.mos_sequence = args->mos.sequence;
      run_pipeline(score, args->options.resolve(*cmd, args->config), {});
    });
  });
}

void register_run(CLI::App& app) {
  struct Args {
    fs::path input, out = "cleanmap-run", config;
    bool overwrite = false;
    bool use_given_poses = false;
    bool online = false;
    MosOptions mos;
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
  add_mos_options(*cmd, args->mos);
  args->options.add_to(*cmd, PresetOptions::kOdometry | PresetOptions::kScorer | PresetOptions::kMapping);
  cmd->callback([cmd, args] {
    run_guarded({args->out, "run", args->options.input_files(args->input, args->config), args->overwrite}, [&] {
      const PipelineConfig cfg = args->options.resolve(*cmd, args->config);
      // An explicit --poses file means "use these poses" too.
      const bool given = args->use_given_poses || !cfg.input.poses.empty();
      PipelineOptions run;
      run.input = args->input;
      run.out = args->out;
      run.odometry = !given;
      run.mapping = true;
      run.offline = !args->online;
      run.command = "run";
      run.mos_predictions = args->mos.enabled;
      run.mos_sequence = args->mos.sequence;
      run_pipeline(run, cfg, {});
    });
  });
}

}  // namespace cleanmap::app
