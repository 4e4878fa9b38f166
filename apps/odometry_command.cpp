#include <cstdio>
#include <fstream>
#include <iomanip>
#include <optional>

#include "apps/commands.hpp"
#include "pipeline/output_claim.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/preset_yaml.hpp"
#include "pipeline/progress.hpp"
#include "pipeline/run_inputs.hpp"
#include "apps/preset_options.hpp"
#include "io/close_checked.hpp"
#include "io/cloud_file.hpp"
#include "odometry/lidar_odometry.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

struct OdometryArgs {
  fs::path input, out = "cleanmap-odometry", config;
  bool overwrite = false;
  bool write_scans = false;
  std::string method = "point_to_plane";
  PresetOptions options;
};

void run_odometry(const CLI::App& cmd, const OdometryArgs& args) {
  const PipelineConfig settings = args.options.resolve(cmd, args.config);
  const OdometryConfig& cfg = settings.odometry;
  validate(cfg);
  SequenceOptions so = sequence_options(settings.input);
  Sequence seq = open_sequence(args.input, so);
  make_dirs(args.out);
  if (args.write_scans) make_dirs(args.out / "scans");
  nlohmann::json summary{{"command", "odometry"},
                         {"input", args.input.string()},
                         {"layout", seq.layout},
                         {"times", seq.times_source},
                         {"method", args.method},
                         {"odometry", to_json(cfg, odometry_fields())}};
  write_summary(args.out, summary, false);
  write_preset(args.out, settings, PresetOptions::kOdometry);

  LidarOdometry odom(cfg);
  odom.method = args.method;
  std::ofstream log(args.out / "odometry_log.csv");
  if (!log) fail(args.out / "odometry_log.csv", "cannot create file");
  log << "scan,stamp,points,iterations,correspondences,inlier_share,rms_residual,threshold,degenerate,recovered,seconds,note\n";
  std::vector<StampedPose> stamped;
  std::vector<double> seconds;
  std::size_t degenerate = 0;
  nlohmann::json empty_scans = nlohmann::json::array();
  double reference_offset = 0.0;
  Progress progress("odometry", seq.size());
  std::optional<LoadedScan> second;  // read at scan 0 to prime the odometry, used at scan 1
  for (std::size_t i = 0; i < seq.size(); ++i) {
    LoadedScan loaded = i == 1 && second ? std::move(*second) : load_scan(seq, i);
    if (loaded.scan.size() == 0) note_empty(loaded, empty_scans);
    if (i == 0 && seq.size() > 1) {  // undistorts the first two sweeps too
      second = load_scan(seq, 1);
      odom.prime(loaded.scan, second->scan);
    }
    auto step = odom.register_scan(loaded.scan);
    reference_offset = step.reference_offset;
    stamped.push_back({loaded.scan.stamp + step.reference_offset, step.pose});
    seconds.push_back(step.seconds);
    degenerate += step.degenerate;
    log << loaded.scan.name << ',' << std::fixed << std::setprecision(6) << loaded.scan.stamp << ','
        << step.points << ',' << step.iterations << ',' << step.correspondences << ','
        << step.inlier_share << ',' << step.rms_residual << ',' << step.threshold << ','
        << step.degenerate << ',' << step.recovered << ',' << step.seconds << ",\"" << step.note << "\"\n";
    if (args.write_scans) {
      // Deskewed already: without the per-point times, a later `score --input OUT` places the
      // points with the scan's pose alone instead of undistorting them a second time.
      Scan deskewed = std::move(step.deskewed);
      deskewed.time.resize(0);
      write_cloud(args.out / "scans" / (loaded.scan.name + ".pcd"), deskewed);
    }
    progress.update(i + 1);
  }
  progress.finish();
  close_checked(log, args.out / "odometry_log.csv");
  if (empty_scans.size() == seq.size()) {
    fail(args.input, "no valid point in any of its " + std::to_string(seq.size()) +
                         " scans (empty, or only NaN / infinite coordinates): nothing to register");
  }

  // With --write-scans, OUT is itself a sequence folder that `cleanmap score --input OUT` reads.
  write_pose_files(args.out, stamped, seq.calib_tr);
  std::vector<double> sorted = seconds;
  std::sort(sorted.begin(), sorted.end());
  summary["scans"] = seq.size();
  summary["degenerate_scans"] = degenerate;
  summary["empty_scans"] = empty_scans;
  summary["pose_reference"] = {{"deskew_reference", cfg.deskew_reference},
                               {"offset_seconds_after_stamp", reference_offset}};
  summary["pose_files"] = pose_files_json(seq.calib_tr, reference_offset);
  summary["seconds_per_scan"] = {{"median", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
                                 {"p99", sorted.empty() ? 0.0 : sorted[(sorted.size() * 99) / 100]}};
  write_summary(args.out, summary, true);
  std::printf("odometry: %zu scans (%zu degenerate) -> %s\n", seq.size(), degenerate,
              (args.out / "poses_kitti.txt").c_str());
}

}  // namespace

void register_odometry(CLI::App& app) {
  auto args = std::make_shared<OdometryArgs>();
  auto* cmd = app.add_subcommand("odometry", "Estimate one pose per scan (deskewing, point-to-plane "
                                             "registration to a local map)");
  cmd->add_option("--input", args->input, "Sequence folder")->required();
  add_output_options(*cmd, args->out, args->overwrite, "Output folder");
  cmd->add_option("--config", args->config, "YAML preset (sections 'input', 'odometry')");
  cmd->add_flag("--write-scans", args->write_scans, "Also write the deskewed scans (OUT/scans)");
  cmd->add_option("--method", args->method, "point_to_plane, or the point_to_point baseline")
      ->check(CLI::IsMember({"point_to_plane", "point_to_point"}))
      ->capture_default_str();
  args->options.add_to(*cmd, PresetOptions::kOdometry);
  cmd->callback([cmd, args] {
    run_guarded({args->out, "odometry", args->options.input_files(args->input, args->config), args->overwrite},
                [&] { run_odometry(*cmd, *args); });
  });
}

}  // namespace cleanmap::app
