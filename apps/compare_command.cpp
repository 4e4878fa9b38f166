#include <cmath>
#include <cstdio>
#include <fstream>

#include "apps/commands.hpp"
#include "pipeline/output_claim.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/pipeline.hpp"
#include "evaluation/trajectory_metrics.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

struct TrajectoryNumbers {
  KittiErrors kitti;
  ApeResult ape;
  RpeResult rpe;
};

TrajectoryNumbers evaluate(const fs::path& est_file, const fs::path& ref_file) {
  const auto est = read_poses(est_file), ref = read_poses(ref_file);
  if (est.size() != ref.size()) {
    fail(ref_file, "has " + std::to_string(ref.size()) + " poses for " + std::to_string(est.size()) + " scans");
  }
  std::vector<Eigen::Isometry3d> e, r;
  for (const auto& p : est) e.push_back(p.pose);
  for (const auto& p : ref) r.push_back(p.pose);
  return {kitti_errors(r, e), absolute_pose_error(r, e, Alignment::kSE3), relative_pose_error(r, e, 1)};
}

struct CompareArgs {
  fs::path input, out = "cleanmap-compare", config, ref;
  bool overwrite = false;
  PresetOptions options;
};

void run_compare(const CLI::App& cmd, const CompareArgs& args, const fs::path& ref) {
  // The reference is read before the first odometry pass, not after it.
  const auto reference = read_poses(ref);
  if (reference.size() < 2) fail(ref, "needs at least 2 reference poses to compare odometry errors");
  PipelineConfig cfg = args.options.resolve(cmd, args.config);
  cfg.input.poses.clear();  // the sequence's own poses are the reference, not an input here
  std::vector<TrajectoryNumbers> results;
  for (bool removal : {false, true}) {
    cfg.odometry.exclude_dynamic = removal;
    const fs::path out = args.out / (removal ? "with" : "without");
    PipelineOptions pass;
    pass.input = args.input;
    pass.out = out;
    pass.odometry = true;
    pass.command = removal ? "compare (removal on)" : "compare (removal off)";
    run_pipeline(pass, cfg, {});
    results.push_back(evaluate(out / "poses_kitti.txt", ref));
  }
  const auto& a = results[0];
  const auto& b = results[1];
  std::printf("\n%-34s %14s %14s\n", "odometry error", "removal off", "removal on");
  std::printf("%-34s %14.3f %14.3f\n", "KITTI t_err [%]", a.kitti.t_err_percent, b.kitti.t_err_percent);
  std::printf("%-34s %14.4f %14.4f\n", "KITTI r_err [deg/100 m]", a.kitti.r_err_deg_per_100m, b.kitti.r_err_deg_per_100m);
  std::printf("%-34s %14.4f %14.4f\n", "APE (SE3) translation RMSE [m]", a.ape.translation.rmse, b.ape.translation.rmse);
  std::printf("%-34s %14.4f %14.4f\n", "RPE (1 frame) translation RMSE [m]", a.rpe.translation.rmse, b.rpe.translation.rmse);
  std::printf("%-34s %14.4f %14.4f\n", "RPE (1 frame) rotation RMSE [deg]", a.rpe.rotation.rmse, b.rpe.rotation.rmse);
  auto js = [](const TrajectoryNumbers& t) {
    return nlohmann::json{{"kitti_t_err_percent", json_number(t.kitti.t_err_percent)},
                          {"kitti_r_err_deg_per_100m", json_number(t.kitti.r_err_deg_per_100m)},
                          {"ape_rmse_m", t.ape.translation.rmse},
                          {"rpe_translation_rmse_m", t.rpe.translation.rmse},
                          {"rpe_rotation_rmse_deg", t.rpe.rotation.rmse}};
  };
  write_summary(args.out, {{"command", "compare"}, {"reference", ref.string()},
                           {"removal_off", js(a)}, {"removal_on", js(b)}}, true);
}

}  // namespace

void register_compare(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand("compare", "Odometry with and without dynamic-point removal from its "
                                            "local map, errors side by side");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  add_output_options(*cmd, args->out, args->overwrite, "Output folder (runs in OUT/without and OUT/with)");
  cmd->add_option("--ref", args->ref, "Reference poses; default <input>/poses.txt");
  cmd->add_option("--config", args->config, "YAML preset (sections input, odometry, scorer)");
  args->options.add_to(*cmd, PresetOptions::kOdometry | PresetOptions::kScorer);
  cmd->callback([cmd, args] {
    const fs::path ref = args->ref.empty() ? args->input / "poses.txt" : args->ref;
    auto files = args->options.input_files(args->input, args->config);
    files.push_back(ref);
    run_guarded({args->out, "compare", files, args->overwrite}, [&] { run_compare(*cmd, *args, ref); });
  });
}

}  // namespace cleanmap::app
