#include <cmath>
#include <cstdio>
#include <map>

#include "apps/commands.hpp"
#include "apps/output_dir.hpp"
#include "apps/progress.hpp"
#include "apps/settings.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "evaluation/dynamic_metrics.hpp"
#include "io/label_file.hpp"
#include "io/score_file.hpp"
#include "mapping/point_cloud_map.hpp"
#include "odometry/deskew.hpp"

namespace cleanmap::app {
namespace fs = std::filesystem;
namespace {

struct ScoreArgs {
  fs::path input, out = "cleanmap-score", config;
  double cloud_voxel = 0.05;
  InputSettings input_cli;
  ScorerConfig scorer_cli;
};

nlohmann::json metrics_json(const MovingConfusion& c) {
  auto num = [](double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
  return {{"iou", num(c.iou())}, {"precision", num(c.precision())}, {"recall", num(c.recall())},
          {"tp", c.tp}, {"fp", c.fp}, {"fn", c.fn}, {"tn", c.tn}};
}

void run_score(const CLI::App& cmd, const ScoreArgs& args) {
  const auto preset = load_optional_preset(args.config);
  const auto input = resolve(cmd, preset, args.config, "input", InputSettings{}, args.input_cli, input_fields());
  const auto cfg = resolve(cmd, preset, args.config, "scorer", ScorerConfig{}, args.scorer_cli, scorer_fields());
  validate(cfg);
  const Sequence seq = open_sequence(args.input, sequence_options(input));
  if (!seq.has_poses()) {
    fail(args.input, "no poses: give --poses FILE or put poses.txt in the folder "
                     "(`cleanmap odometry` estimates them)");
  }
  make_dirs(args.out / "scores");
  make_dirs(args.out / "labels");
  nlohmann::json summary{{"command", "score"},
                         {"input", args.input.string()},
                         {"layout", seq.layout},
                         {"poses", seq.poses_source},
                         {"times", seq.times_source},
                         {"input_settings", to_json(input, input_fields())},
                         {"scorer", to_json(cfg, scorer_fields())}};
  write_summary(args.out, summary, false);

  SpatiotemporalScorer scorer(cfg);
  PointCloudMap dynamic_cloud(0.0), static_cloud(args.cloud_voxel);
  std::map<std::size_t, std::vector<std::uint32_t>> truth;  // labels of scans awaiting scores
  MovingConfusion total;
  nlohmann::json per_scan = nlohmann::json::array();
  std::size_t points = 0, dynamic_points = 0, unscored = 0, dropped = 0;
  Progress progress("score", seq.size());

  auto emit = [&](ScoredScan& r) {
    const Scan& scan = r.scan;
    std::vector<std::uint32_t> labels(scan.size());
    std::vector<std::uint8_t> keep_static(scan.size());
    std::size_t n_dyn = 0, n_unscored = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      labels[i] = r.dynamic[i] ? kLabelMoving : std::isnan(r.score[i]) ? kLabelUnscored : kLabelStatic;
      keep_static[i] = !r.dynamic[i];
      n_dyn += r.dynamic[i];
      n_unscored += std::isnan(r.score[i]) && !r.dynamic[i];
    }
    write_scores(args.out / "scores" / (scan.name + ".bin"),
                 to_input_order(scan, r.score, std::nanf("")));
    write_labels(args.out / "labels" / (scan.name + ".label"),
                 to_input_order(scan, labels, kLabelUnscored));
    dynamic_cloud.add(scan, r.dynamic, r.score, r.index);
    static_cloud.add(scan, keep_static, r.score, r.index);
    nlohmann::json js{{"scan", scan.name},
                      {"points", scan.size()},
                      {"dynamic", n_dyn},
                      {"unscored", n_unscored},
                      {"window", {r.scans_before, r.scans_after}},
                      {"full_window", r.scans_before == cfg.window_half && r.scans_after == cfg.window_half},
                      {"voxel_size", r.voxel_size},
                      {"downsampled", r.downsampled},
                      {"dynamic_downsampled_before_completion", r.dynamic_before_completion},
                      {"dynamic_downsampled", r.dynamic_downsampled},
                      {"seconds", r.seconds}};
    const auto& gt = truth[r.index];
    if (!gt.empty()) {
      MovingConfusion c;
      const Eigen::Vector3f origin = scan.pose->translation().cast<float>();
      for (std::size_t i = 0; i < scan.size(); ++i) {
        if (input.eval_max_range > 0 &&
            (scan.points.col(static_cast<Eigen::Index>(i)) - origin).norm() > input.eval_max_range) {
          continue;
        }
        count(c, r.dynamic[i], is_moving_label(gt[i]), !std::isnan(r.score[i]));
      }
      js["moving"] = metrics_json(c);
      total += c;
    }
    truth.erase(r.index);
    points += scan.size();
    dynamic_points += n_dyn;
    unscored += n_unscored;
    per_scan.push_back(js);
  };

  for (std::size_t i = 0; i < seq.size(); ++i) {
    LoadedScan loaded = load_scan(seq, i);
    dropped += loaded.dropped_non_finite;
    truth[i] = std::move(loaded.labels);
    const Scan world = to_world(loaded.scan, sweep_motion(seq.poses, seq.times, i));
    for (auto& r : scorer.push(world)) emit(r);
    progress.update(i + 1);
  }
  for (auto& r : scorer.finish()) emit(r);
  progress.finish();

  dynamic_cloud.write(args.out / "dynamic.pcd");
  static_cloud.write(args.out / "static.pcd");
  summary["scans"] = seq.size();
  summary["points"] = points;
  summary["dynamic_points"] = dynamic_points;
  summary["unscored_points"] = unscored;
  summary["non_finite_dropped"] = dropped;
  summary["seconds"] = progress.elapsed_s();
  summary["per_scan"] = per_scan;
  if (seq.has_labels()) summary["moving"] = metrics_json(total);
  write_summary(args.out, summary, true);
  std::printf("score: %zu scans, %zu of %zu points dynamic -> %s\n", seq.size(), dynamic_points,
              points, args.out.c_str());
  if (seq.has_labels()) {
    std::printf("  moving class vs labels: IoU %.3f  precision %.3f  recall %.3f\n", total.iou(),
                total.precision(), total.recall());
  }
}

}  // namespace

void register_score(CLI::App& app) {
  auto args = std::make_shared<ScoreArgs>();
  auto* cmd = app.add_subcommand("score", "Score every point of a registered sequence as dynamic "
                                          "or static (spatiotemporal normals)");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
  cmd->add_option("--config", args->config, "YAML preset (sections 'input', 'scorer')");
  cmd->add_option("--cloud-voxel", args->cloud_voxel, "Voxel filter of static.pcd, m (0 = all)")
      ->capture_default_str();
  add_options(*cmd, args->input_cli, input_fields());
  add_options(*cmd, args->scorer_cli, scorer_fields());
  cmd->callback([cmd, args] {
    try {
      run_score(*cmd, *args);
    } catch (const Error& e) {
      if (fs::is_directory(args->out)) write_summary(args->out, {{"command", "score"}}, false, e.what());
      throw;
    }
  });
}

}  // namespace cleanmap::app
