// The stages of a run after scoring: the occupancy opinion and the map (stage 3), the per-scan
// files and metrics (stage 4), and what is written once the passes are done.
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipeline/mos_layout.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/pipeline_run.hpp"
#include "pipeline/run_summary.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "io/depth_image.hpp"
#include "io/label_file.hpp"
#include "io/score_file.hpp"
#include "mapping/free_space_vote.hpp"
#include "mapping/whole_log_vote.hpp"

namespace cleanmap::pipeline {

void PipelineRun::map_scan(ScoredScan& r, const std::optional<SweepOrigin>& sensor) {
  if (!opt.mapping) return;
  const auto t = Clock::now();
  std::optional<StreamEnds::Judgement> judgement;
  {
    std::lock_guard<std::mutex> lock(judgements_mutex);
    if (auto it = judgements.find(r.index); it != judgements.end()) {
      judgement = std::move(it->second);
      judgements.erase(it);
    }
  }
  if (judgement) {
    ends_vetoed += StreamEnds::judge(r, *judgement, visibility_config(cfg), cfg.mapping.free_space_objects,
                                     cfg.mapping.free_space_voxel);
  }
  Scan& scan = r.scan;
  if (cfg.mapping.free_space) {
    const auto objects = free_space_objects(
        scan.points, [&](const Eigen::Matrix3Xf& sub) { return segment_ground(sub, cfg.scorer.ground); },
        [&](const Eigen::Matrix3Xf& sub) { return octo->hits_in_free_space(sub); }, cfg.mapping.free_space_objects,
        cfg.mapping.free_space_voxel);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (objects[i] && !r.dynamic[i]) {
        r.dynamic[i] = 1;
        ++free_space_added;
      }
    }
  }
  if (r.index % static_cast<std::size_t>(std::max(1, cfg.mapping.insert_every)) == 0) {
    std::vector<std::int32_t> keep;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!r.dynamic[i]) keep.push_back(static_cast<std::int32_t>(i));
    }
    const SweepOrigin from = sensor ? *sensor : SweepOrigin{scan.pose->translation()};
    auto times_of = [&](const std::vector<std::int32_t>& idx) {
      return scan.has_time() ? Eigen::VectorXf(scan.time(idx)) : Eigen::VectorXf();
    };
    octo->insert(scan.points(Eigen::all, keep), times_of(keep), from);
    if (visibility) {
      const auto solid = seen_standing(*visibility, scan.points, keep);
      octo->pin(scan.points(Eigen::all, solid), times_of(solid), from);
    }
  }
  mapping_s += since(t);
}

void PipelineRun::feed_back(const ScoredScan& r) {
  if (!odom || !cfg.odometry.exclude_dynamic) return;
  std::vector<Eigen::Vector3d> moving;
  for (std::size_t i = 0; i < r.scan.size(); ++i) {
    if (r.dynamic[i]) moving.push_back(r.scan.points.col(static_cast<Eigen::Index>(i)).cast<double>());
  }
  if (moving.empty()) return;
  std::lock_guard<std::mutex> lock(odom_mutex);
  odom->remove_dynamic(moving);
}

namespace {

// summary.json's entry of one scan.
nlohmann::json scan_json(const ScoredScan& r, std::size_t n_dyn, std::size_t n_unscored, int window_half) {
  return {{"scan", r.scan.name},
          {"points", r.scan.size()},
          {"dynamic", n_dyn},
          {"unscored", n_unscored},
          {"window", {r.scans_before, r.scans_after}},
          {"full_window", r.scans_before == window_half && r.scans_after == window_half},
          {"voxel_size", r.voxel_size},
          {"downsampled", r.downsampled},
          {"dynamic_downsampled_before_completion", r.dynamic_before_completion},
          {"dynamic_downsampled", r.dynamic_downsampled},
          {"tracked_points", r.tracked_points},
          {"scoring_seconds", r.seconds}};
}

}  // namespace

void PipelineRun::write_scan(ScoredScan& r, const std::vector<std::uint32_t>& gt) {
  const auto t = Clock::now();
  Scan& scan = r.scan;
  std::vector<std::uint8_t> keep_static(scan.size());
  std::vector<std::uint32_t> labels(scan.size());
  std::size_t n_dyn = 0, n_unscored = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    labels[i] = r.dynamic[i] ? kLabelMoving : std::isnan(r.score[i]) ? kLabelUnscored : kLabelStatic;
    keep_static[i] = !r.dynamic[i];
    n_dyn += r.dynamic[i];
    n_unscored += std::isnan(r.score[i]) && !r.dynamic[i];
  }
  if (opt.mapping && cfg.mapping.write_raw_map) {
    raw_cloud.add(scan, std::vector<std::uint8_t>(scan.size(), 1), r.score, r.index);
  }
  if (!offline) feed_back(r);
  auto scores_in_order = to_input_order(scan, r.score, std::nanf(""));
  auto in_order = to_input_order(scan, labels, kLabelUnscored);
  static_cloud.add(scan, keep_static, r.score, r.index);
  if (opt.streamed) {  // OnlineMapper: no files; the map's static cloud is all it keeps
    if (opt.on_scan) opt.on_scan(r, std::move(in_order), std::move(scores_in_order));
    points += scan.size();
    dynamic_points += n_dyn;
    write_s += since(t);
    return;
  }
  write_scores(opt.out / "scores" / (scan.name + ".bin"), scores_in_order);
  write_labels(opt.out / "labels" / (scan.name + ".label"), in_order);
  if (!mos_dir.empty()) write_labels(mos_label_file(mos_dir, scan, r.index), mos_labels(scan, r.dynamic));
  if (seq.image_width > 0) {
    write_label_mask(opt.out / "labels" / (scan.name + ".png"), in_order, seq.image_width, seq.image_height);
  }
  dynamic_cloud.add(scan, r.dynamic, r.score, r.index);

  nlohmann::json js = scan_json(r, n_dyn, n_unscored, cfg.scorer.window_half);
  if (!gt.empty()) {
    MovingConfusion c;
    const Eigen::Vector3f origin = scan.pose->translation().cast<float>();
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (cfg.input.eval_max_range > 0 &&
          (scan.points.col(static_cast<Eigen::Index>(i)) - origin).norm() > cfg.input.eval_max_range) {
        continue;
      }
      count(c, r.dynamic[i], is_moving_label(gt[i]), !std::isnan(r.score[i]));
    }
    js["moving"] = metrics_json(c);
    total += c;
  }
  points += scan.size();
  dynamic_points += n_dyn;
  unscored += n_unscored;
  tracked += r.tracked_points;
  per_scan.push_back(js);
  write_s += since(t);
}

void PipelineRun::write_maps() {
  const auto t = Clock::now();
  if (opt.mapping) {  // an empty map is no result: nothing is written that looks like one
    if (octo->points_beyond_reach() > 0 && octo->leaf_count() == 0) {
      char msg[240];
      std::snprintf(msg, sizeof msg, "map: every point lay beyond the OctoMap's reach (%.0f m from the map origin at "
                    "%g m cells): the map would be empty; give --map-origin near the log", octo->reach(),
                    cfg.mapping.map.resolution);
      throw Error(msg);
    }
  }
  if (opt.mapping && offline) cells_pinned = octo->occupy_pinned();
  // The map files are independent of each other: written side by side, but the large clouds
  // one after another (each write converts a whole cloud for PCL: two at once doubled the peak
  // memory), and the OctoMap ones in order (writing the .bt prunes the tree). An error in any
  // task is rethrown here.
  tbb::parallel_invoke(
      [&] { dynamic_cloud.write(opt.out / (opt.mapping ? "map_dynamic.pcd" : "dynamic.pcd")); },
      [&] {
        if (opt.mapping) {
          static_cloud.write({opt.out / "map_static.pcd", opt.out / "map_static.ply"});
        } else {
          static_cloud.write(opt.out / "static.pcd");
        }
        if (opt.mapping && cfg.mapping.write_raw_map) raw_cloud.write(opt.out / "map_raw.pcd");
      },
      [&] {
        if (!opt.mapping) return;
        octo->write_binary(opt.out / "map.bt");
        octo->write_full(opt.out / "map.ot");
        if (cfg.mapping.occupancy_grid) {
          octo->write_occupancy_grid(opt.out / "map_2d.pgm", cfg.mapping.grid_z_min, cfg.mapping.grid_z_max);
        }
      });
  if (use_odometry) write_pose_files(opt.out, poses, seq.calib_tr);
  write_s += since(t);
}

void PipelineRun::summarise(nlohmann::json& summary, double seconds) {
  if (opt.mapping) {
    summary["octomap_leaves"] = octo->leaf_count();
    summary["octomap_points_beyond_reach"] = octo->points_beyond_reach();
    if (octo->points_beyond_reach() > 0) {
      std::fprintf(stderr, "%s: warning: %zu points lay beyond the OctoMap's reach (%.0f m from the map origin "
                   "at %g m cells) and are not in map.bt / map.ot: give --map-origin near the log, or coarser "
                   "--resolution\n", opt.command.c_str(), octo->points_beyond_reach(), octo->reach(),
                   cfg.mapping.map.resolution);
    }
  }
  if (opt.mapping && offline) summary["octomap_cells_pinned"] = cells_pinned;
  if (offline) summary["spill_bytes"] = spill_bytes;
  if (use_odometry) {
    summary["pose_files"] = pose_files_json(seq.calib_tr, poses.empty() ? 0.0 : poses.front().stamp - seq.times.front());
  }
  summary["scans"] = seq.size();
  summary["points"] = points;
  summary["static_points"] = points - dynamic_points;
  summary["dynamic_points"] = dynamic_points;
  summary["unscored_points"] = unscored;
  summary["free_space_added_points"] = free_space_added;
  if (offline) {
    summary["visibility"] = {{"cells", visibility->cells()},
                             {"resolution", cfg.mapping.visibility.resolution},
                             {"added_points", void_added},
                             {"vetoed_points", void_vetoed},
                             {"floor_cells", floor.size()}};
  }
  if (ends) {
    summary["stream_ends"] = {{"scans_kept", ends->keep()},
                              {"vetoed_points", ends_vetoed}};
  }
  summary["tracked_points"] = tracked;
  summary["non_finite_dropped"] = dropped;
  summary["out_of_range_dropped"] = out_of_range;  // beyond 1e6 m or 10 s (io/scan.hpp)
  if (seq.world_frame) summary["viewpoint_missing_scans"] = viewpoints_missing;
  summary["empty_scans"] = empty_scans;
  summary["platform_mask"] = {{"masked_points", masked}, {"learnt_cells", mask.cells.size()},
                              {"crop_box", !mask.crop_box.empty()}, {"note", mask.note}};
  summary["seconds"] = seconds;
  summary["scans_per_second"] = seconds > 0 ? static_cast<double>(seq.size()) / seconds : 0.0;
  nlohmann::json stages{{"read", read_s},
                        {"odometry", odometry_s},
                        {"scoring", preparing_s + scoring_s},
                        {"mapping", mapping_s},
                        {"write", write_s}};
  if (offline) {
    stages["visibility"] = visibility_s + rays_s;
    stages["judging"] = judging_s;
  }
  summary["stage_seconds"] = stages;
  // The scoring stage's two halves: the scorer's preparation of a scan (downsampling, ground,
  // its cells) runs in a stage of its own, beside the scoring of the scan before.
  summary["scoring_seconds"] = {{"preparing", preparing_s}, {"scoring", scoring_s}};
  // The rate a live sensor would see: input scans through the whole pipeline per second in
  // the steady state, from the first scan that released output to the one before the last
  // (the scorer's first full window releases N scans at once; after the last scan, the held
  // scans leave one flush item each, not counted). Counting outputs up to the last N instead
  // had read 22 scans/s as 28 without the tracker and as 16 with it.
  if (!offline && finished_at.size() >= 3) {
    const double span = std::chrono::duration<double>(finished_at[finished_at.size() - 2] - finished_at[0]).count();
    summary["sustained_scans_per_second"] = span > 0 ? static_cast<double>(finished_at.size() - 2) / span : 0.0;
  }
  // Input to labels written, per scan (online): the window's delay (N scans) plus the work.
  // Read from a file, input arrives as fast as stage 1 takes it, so this is the run's own
  // delay; a live sensor adds N / rate_hz of waiting for the window's future scans.
  if (!offline && !latency.empty()) {
    auto sorted = latency;
    std::sort(sorted.begin(), sorted.end());
    const auto at = [&](double q) {
      return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5)];
    };
    summary["latency_seconds"] = {{"median", at(0.5)}, {"p95", at(0.95)}, {"max", sorted.back()}};
  }
  summary["per_scan"] = per_scan;
  if (seq.has_labels()) summary["moving"] = metrics_json(total);
  write_summary(opt.out, summary, true);

  std::printf("%s: %zu scans, %zu of %zu points dynamic (%.1f scans/s)\n", opt.command.c_str(), seq.size(),
              dynamic_points, points, seq.size() / std::max(seconds, 1e-9));
  if (seq.has_labels()) {
    std::printf("  moving class vs labels: IoU %.3f  precision %.3f  recall %.3f\n", total.iou(), total.precision(),
                total.recall());
  }
  std::printf("  outputs in %s:", opt.out.c_str());
  if (opt.mapping) std::printf(" map.bt map.ot map_static.pcd map_static.ply map_dynamic.pcd");
  else std::printf(" static.pcd dynamic.pcd");
  if (use_odometry) std::printf(" poses_kitti.txt poses_tum.txt");
  std::printf(" scores/ labels/ summary.json\n");
  if (!mos_dir.empty()) std::printf("  SemanticKITTI MOS predictions in %s\n", mos_dir.c_str());
}

}  // namespace cleanmap::pipeline
