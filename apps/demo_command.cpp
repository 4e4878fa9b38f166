#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "apps/commands.hpp"
#include "apps/cli_fields.hpp"
#include "apps/installed_file.hpp"
#include "apps/preset_options.hpp"
#include "pipeline/output_claim.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/progress.hpp"
#include "io/cloud_file.hpp"
#include "io/label_file.hpp"
#include "io/pose_file.hpp"
#include "simulation/synthetic_depth.hpp"
#include "simulation/synthetic_lidar.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

auto synthetic_fields() {
  return std::make_tuple(
      // Upper bounds keep a typo from allocating what no sensor produces (1024 beams x 65536).
      CLEANMAP_FIELD_IN("scans", scans, (Range{1, 100000}), "Number of scans to simulate"),
      CLEANMAP_FIELD_IN("seed", seed, kNonNegative, "Random seed (scene layout and range noise)"),
      CLEANMAP_FIELD_IN("beams", lidar.beams, (Range{1, 1024}), "Lidar beams (rows)"),
      CLEANMAP_FIELD_IN("columns", lidar.columns, (Range{1, 65536}), "Firings per revolution (columns)"),
      CLEANMAP_FIELD_IN("rate_hz", lidar.rate_hz, (Range{0.1, 1000}), "Revolutions per second"),
      CLEANMAP_FIELD_IN("fov_up_deg", lidar.fov_up_deg, (Range{-90, 90}), "Upper edge of the vertical field of view"),
      CLEANMAP_FIELD_IN("fov_down_deg", lidar.fov_down_deg, (Range{-90, 90}), "Lower edge of the vertical field of view"),
      CLEANMAP_FIELD_IN("max_range", lidar.max_range, (Range{0.1, 10000}), "Maximum range, m"),
      CLEANMAP_FIELD_IN("range_noise", lidar.range_noise, (Range{0, 10}), "Range noise (std. dev.), m"));
}

struct DemoArgs {
  fs::path out = "cleanmap-demo";
  fs::path config;
  bool overwrite = false;
  bool generate_only = false;
  bool static_scene = false;
  std::string sensor = "lidar";
  SyntheticConfig cli;  // values as given on the command line
};

// Where the demo's files are, as its last lines.
void print_outputs(const fs::path& seq, const char* contents, const DemoArgs& args) {
  std::printf("demo outputs:\n  sequence:   %s (%s)\n", seq.c_str(), contents);
  if (args.generate_only) return;
  const fs::path run = args.out / "run";
  std::printf("  clean map:  %s (OctoMap), %s\n  removed:    %s\n  poses:      %s\n"
              "  per point:  %s, %s\n  summary:    %s\n",
              (run / "map.bt").c_str(), (run / "map_static.pcd").c_str(), (run / "map_dynamic.pcd").c_str(),
              (run / "poses_kitti.txt").c_str(), (run / "scores").c_str(), (run / "labels").c_str(),
              (run / "summary.json").c_str());
}

// The arm preset (config/rgbd-arm.yaml, installed or in the source tree): the depth demo runs
// with exactly what a user of that preset gets.
PipelineConfig depth_demo_config() {
  const fs::path preset = installed_file("config/rgbd-arm.yaml", fs::path(CLEANMAP_CONFIG_DIR) / "rgbd-arm.yaml");
  const auto root = load_preset(preset);
  PipelineConfig c;
  if (root["input"]) apply_yaml(root["input"], c.input, input_fields(), preset, "input");
  if (root["odometry"]) apply_yaml(root["odometry"], c.odometry, odometry_fields(), preset, "odometry");
  if (root["scorer"]) apply_yaml(root["scorer"], c.scorer, scorer_fields(), preset, "scorer");
  if (root["mapping"]) apply_yaml(root["mapping"], c.mapping, mapping_fields(), preset, "mapping");
  return c;
}

// The depth-camera demo: a camera on a robot arm over a table while a hand pushes an object
// (the paper's second experiment), in the TUM RGB-D layout, then `run` with the arm preset.
void run_depth_demo(const DemoArgs& args, int frames) {
  const fs::path seq = args.out / "sequence";
  nlohmann::json summary;
  summary["command"] = "demo";
  summary["sensor"] = "depth";
  write_summary(args.out, summary, false);
  write_table_sequence(seq, make_table_scene(), frames, 30.0, 1);
  std::printf("demo: synthetic depth sequence (%d frames of 320 x 240, TUM RGB-D layout) in %s\n", frames, seq.c_str());
  std::fflush(stdout);  // before the run's progress on stderr
  summary["sequence"] = seq.string();
  if (!args.generate_only) {
    PipelineOptions run;
    run.input = seq;
    run.out = args.out / "run";
    run.odometry = run.mapping = run.offline = true;
    run.command = "demo run";
    run_pipeline(run, depth_demo_config(), {});
    summary["run"] = run.out.string();
  }
  write_summary(args.out, summary, true);
  print_outputs(seq, "depth/, depth.txt, groundtruth.txt, camera.yaml, labels/", args);
}

void run_demo(const CLI::App& cmd, const DemoArgs& args) {
  if (args.sensor == "depth") return run_depth_demo(args, cmd.count("--scans") ? args.cli.scans : 90);
  SyntheticConfig cfg;
  cfg.lidar.columns = 1024;  // the demo's default: a quick, still realistic 64 x 1024 sensor
  const auto fields = synthetic_fields();
  if (!args.config.empty()) {
    const auto root = load_preset(args.config);
    if (root["synthetic"]) apply_yaml(root["synthetic"], cfg, fields, args.config, "synthetic");
  }
  SyntheticConfig cli = args.cli;
  override_from_cli(cmd, cfg, cli, fields);
  if (cfg.scans < 1 || cfg.lidar.beams < 1 || cfg.lidar.columns < 1 || !(cfg.lidar.rate_hz > 0)) {
    throw Error("demo: scans, beams, columns and rate_hz must be positive");
  }
  // (issue 45: an inverted field of view was accepted and simulated upside down)
  if (!(cfg.lidar.fov_up_deg > cfg.lidar.fov_down_deg)) {
    throw Error("demo: --fov-up-deg (" + std::to_string(cfg.lidar.fov_up_deg) + ") must be above --fov-down-deg (" +
                std::to_string(cfg.lidar.fov_down_deg) + ")");
  }

  const fs::path seq = args.out / "sequence";
  make_dirs(seq / "scans");
  make_dirs(seq / "labels");
  nlohmann::json summary;
  summary["command"] = "demo";
  summary["synthetic"] = to_json(cfg, fields);
  write_summary(args.out, summary, false);

  auto world = make_street_world(cfg.seed);
  if (args.static_scene) {
    world.objects.erase(std::remove_if(world.objects.begin(), world.objects.end(),
                                       [](const SceneObject& o) { return o.moving(); }),
                        world.objects.end());
  }
  std::vector<Eigen::Isometry3d> poses;
  std::vector<StampedPose> stamped;
  std::vector<double> times;
  std::size_t points = 0, moving = 0;
  Progress progress("demo: simulating", static_cast<std::size_t>(cfg.scans));
  for (int i = 0; i < cfg.scans; ++i) {
    const auto s = simulate_scan(world, cfg.lidar, static_cast<std::size_t>(i), cfg.seed);
    write_cloud(seq / "scans" / (s.scan.name + ".pcd"), s.scan);
    write_labels(seq / "labels" / (s.scan.name + ".label"), s.labels);
    poses.push_back(*s.scan.pose);
    stamped.push_back({s.scan.stamp, *s.scan.pose});
    times.push_back(s.scan.stamp);
    points += s.scan.size();
    for (auto l : s.labels) moving += is_moving_label(l) ? 1 : 0;
    progress.update(static_cast<std::size_t>(i + 1));
  }
  progress.finish();
  write_kitti_poses(seq / "poses.txt", poses);
  write_tum_poses(seq / "poses_tum.txt", stamped);
  {
    std::FILE* f = std::fopen((seq / "times.txt").c_str(), "w");
    if (!f) fail(seq / "times.txt", "cannot create file");
    for (double t : times) std::fprintf(f, "%.6f\n", t);
    std::fclose(f);
  }
  summary["sequence"] = seq.string();
  summary["points"] = points;
  summary["moving_points"] = moving;
  std::printf("demo: synthetic sequence (%d scans, %zu points, %zu moving) in %s\n", cfg.scans,
              points, moving, seq.c_str());
  if (!args.generate_only) {
    // The whole pipeline on it, from raw scans: odometry, scoring, mapping. Ground truth
    // poses are not used; the labels only score the result.
    PipelineConfig pipeline;
    pipeline.scorer.voxel_size = 0.1;  // the scene spans 200 m: the relative d_v would be 0.4 m
    pipeline.input.eval_max_range = 20.0;
    PipelineOptions run;
    run.input = seq;
    run.out = args.out / "run";
    run.odometry = run.mapping = run.offline = true;
    run.command = "demo run";
    run_pipeline(run, pipeline, {});
    summary["run"] = (args.out / "run").string();
  }
  write_summary(args.out, summary, true);
  print_outputs(seq, "scans/, labels/, poses.txt, times.txt", args);
}

}  // namespace

void register_demo(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  auto* cmd = app.add_subcommand("demo", "Simulate a street (moving cars and pedestrians) seen by "
                                         "a spinning lidar, then build its clean map from the raw scans");
  add_output_options(*cmd, args->out, args->overwrite, "Output folder");
  cmd->add_option("--config", args->config, "YAML preset (section 'synthetic')");
  cmd->add_flag("--generate-only", args->generate_only, "Only write the synthetic sequence");
  cmd->add_flag("--static-scene", args->static_scene, "Nothing moves but the sensor (a check: nothing should be removed)");
  cmd->add_option("--sensor", args->sensor, "lidar (a street) or depth (a camera on an arm over a table, TUM RGB-D layout)")
      ->check(CLI::IsMember({"lidar", "depth"}))
      ->capture_default_str();
  add_options(*cmd, args->cli, synthetic_fields());
  cmd->callback([cmd, args] {
    run_guarded({args->out, "demo", {args->config}, args->overwrite}, [&] { run_demo(*cmd, *args); });
  });
}

}  // namespace cleanmap::app
