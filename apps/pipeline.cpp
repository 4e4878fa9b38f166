#include "apps/pipeline.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <mutex>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_pipeline.h>

#include "apps/mos_layout.hpp"
#include "apps/offline_pass.hpp"
#include "apps/offline_spill.hpp"
#include "apps/run_inputs.hpp"
#include "apps/run_summary.hpp"
#include "apps/output_dir.hpp"
#include "apps/interrupt.hpp"
#include "apps/preset_yaml.hpp"
#include "apps/progress.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "dynamics/object_tracker.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "evaluation/dynamic_metrics.hpp"
#include "io/depth_image.hpp"
#include "io/label_file.hpp"
#include "io/score_file.hpp"
#include "mapping/free_space_vote.hpp"
#include "mapping/octomap_builder.hpp"
#include "mapping/point_cloud_map.hpp"
#include "mapping/visibility_map.hpp"
#include "odometry/deskew.hpp"
#include "odometry/level_frame.hpp"
#include "odometry/lidar_odometry.hpp"

namespace cleanmap::app {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Moves `more` onto the end of `into`.
void append(std::vector<ScoredScan>& into, std::vector<ScoredScan> more) {
  std::move(more.begin(), more.end(), std::back_inserter(into));
}

}  // namespace

void run_pipeline(const PipelineOptions& opt, const PipelineConfig& cfg, nlohmann::json summary) {
  validate(cfg.scorer);
  if (opt.mapping) validate(cfg.mapping.map);
  if (opt.mapping && cfg.mapping.free_space) validate(cfg.mapping.free_space_objects, "mapping: free space vote");
  const bool offline = opt.offline && opt.mapping;
  if (offline) validate(cfg.mapping.visibility);
  const Sequence seq = open_sequence(opt.input, sequence_options(cfg.input));
  // DynamicMap sequences are registered already: no odometry, and the output keeps every raw
  // input point that is not removed (never voxel centres or re-posed copies), as that
  // benchmark scores kept points by distance.
  const bool use_odometry = opt.odometry && !seq.world_frame;
  if (use_odometry) validate(cfg.odometry);
  validate(cfg.input.platform);
  if (!use_odometry && !seq.has_poses() && !seq.world_frame) {
    fail(opt.input, "no poses: give --poses FILE or put poses.txt in the folder "
                    "(`cleanmap odometry` estimates them, `cleanmap run` does it itself)");
  }
  make_dirs(opt.out / "scores");
  make_dirs(opt.out / "labels");
  const fs::path mos_dir = opt.mos_predictions ? mos_predictions_dir(opt.out, opt.input, opt.mos_sequence) : fs::path();
  if (!mos_dir.empty()) make_dirs(mos_dir);
  summary["command"] = opt.command;
  summary["input"] = opt.input.string();
  summary["layout"] = seq.layout;
  if (!mos_dir.empty()) summary["mos_predictions"] = mos_dir.string();
  summary["mode"] = offline ? "offline" : "online";
  summary["times"] = seq.times_source;
  summary["poses"] = use_odometry ? "odometry" : seq.world_frame ? "VIEWPOINT (world-frame scans)" : seq.poses_source;
  summary["input_settings"] = to_json(cfg.input, input_fields());
  summary["scorer"] = to_json(cfg.scorer, scorer_fields());
  if (use_odometry) summary["odometry"] = to_json(cfg.odometry, odometry_fields());
  if (opt.mapping) summary["mapping"] = to_json(cfg.mapping, mapping_fields());
  summary["libraries"] = library_versions();
  write_summary(opt.out, summary, false);
  write_preset(opt.out, cfg, PresetOptions::kScorer | (use_odometry ? PresetOptions::kOdometry : 0) |
                                 (opt.mapping ? PresetOptions::kMapping : 0));
  const PlatformMask mask = platform_mask(seq, cfg.input.platform);
  if (!mask.note.empty()) std::fprintf(stderr, "%s: platform mask: none learnt: %s\n", opt.command.c_str(), mask.note.c_str());
  std::size_t masked = 0;

  std::unique_ptr<LidarOdometry> odom;
  if (use_odometry) odom = std::make_unique<LidarOdometry>(cfg.odometry);
  std::unique_ptr<OctoMapBuilder> octo;
  if (opt.mapping) octo = std::make_unique<OctoMapBuilder>(cfg.mapping.map);
  std::unique_ptr<VisibilityMap> visibility;
  const fs::path spill_dir = opt.out / ".offline";
  if (offline) {
    VisibilityConfig v = cfg.mapping.visibility;
    v.prob_hit = cfg.mapping.map.prob_hit;  // one weighing of hits and misses for both maps
    v.prob_miss = cfg.mapping.map.prob_miss;
    v.free_probability = cfg.mapping.map.free_probability;
    visibility = std::make_unique<VisibilityMap>(v);
    make_dirs(spill_dir);
  }
  // The spills go whatever happens: a run stopped by bad input leaves no half of them behind.
  struct RemoveAtExit {
    fs::path dir;
    ~RemoveAtExit() {
      std::error_code ignored;
      if (!dir.empty()) fs::remove_all(dir, ignored);
    }
  } spills{offline ? spill_dir : fs::path()};
  std::size_t void_added = 0, void_vetoed = 0;
  SpatiotemporalScorer scorer(cfg.scorer);
  ObjectTracker tracker(cfg.scorer.tracks, cfg.scorer.window_half, cfg.scorer.objects.radius);
  const double cloud_voxel = seq.world_frame ? 0.0 : opt.mapping ? cfg.mapping.cloud_voxel : 0.05;
  PointCloudMap dynamic_cloud(0.0), static_cloud(cloud_voxel), raw_cloud(cloud_voxel);
  std::vector<StampedPose> poses;
  MovingConfusion total;
  nlohmann::json per_scan = nlohmann::json::array();
  nlohmann::json empty_scans = nlohmann::json::array();  // {scan, reason} of scans with no valid point
  std::size_t points = 0, dynamic_points = 0, unscored = 0, dropped = 0, free_space_added = 0,
              tracked = 0;
  // Busy time of each stage (they overlap: the sum exceeds the wall time).
  std::map<std::string, double> stage_seconds{{"read", 0}, {"odometry", 0}, {"scoring", 0},
                                              {"mapping", 0}, {"write", 0}};
  Progress progress(offline ? opt.command + " (pass 1 of 2)" : opt.command, seq.size());

  std::mutex odom_mutex;  // the pipeline's first stage registers, its last feeds dynamics back
  // The odometry's world frame, levelled on the first scan when asked (identity otherwise).
  Eigen::Isometry3d level = Eigen::Isometry3d::Identity();
  std::vector<Clock::time_point> finished_at;  // when each input scan that released output was written
  std::size_t scans_done = 0;                  // scans through every stage of this pass
  double mapping_s = 0, write_s = 0;
  // Pipeline stage 3: the occupancy opinion, then the static points into the map.
  auto map_scan = [&](ScoredScan& r) {
    if (!opt.mapping) return;
    const auto t = Clock::now();
    Scan& scan = r.scan;
    if (cfg.mapping.free_space) {
      const auto objects = free_space_objects(
          scan.points,
          [&](const Eigen::Matrix3Xf& sub) {
            return segment_ground(sub, cfg.scorer.ground);
          },
          [&](const Eigen::Matrix3Xf& sub) { return octo->hits_in_free_space(sub); },
          cfg.mapping.free_space_objects, cfg.mapping.free_space_voxel);
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
      octo->insert(scan.points(Eigen::all, keep), scan.pose->translation());
    }
    mapping_s += since(t);
  };

  // The scorer's dynamic points leave the odometry's local map (`exclude_dynamic`). Offline it
  // happens in pass 1, while odometry still runs: in pass 2 it came after the last pose.
  auto feed_back = [&](const ScoredScan& r) {
    if (!odom || !cfg.odometry.exclude_dynamic) return;
    std::vector<Eigen::Vector3d> moving;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {  // back into the odometry's own frame
      if (r.dynamic[i]) moving.push_back(level.inverse() * r.scan.points.col(static_cast<Eigen::Index>(i)).cast<double>());
    }
    if (moving.empty()) return;
    std::lock_guard<std::mutex> lock(odom_mutex);
    odom->remove_dynamic(moving);
  };

  // Pipeline stage 4: per-scan files, map clouds, metrics, and the odometry feedback.
  auto write_scan = [&](ScoredScan& r, const std::vector<std::uint32_t>& gt) {
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
    write_scores(opt.out / "scores" / (scan.name + ".bin"), to_input_order(scan, r.score, std::nanf("")));
    write_labels(opt.out / "labels" / (scan.name + ".label"), to_input_order(scan, labels, kLabelUnscored));
    if (!mos_dir.empty()) write_labels(mos_label_file(mos_dir, scan, r.index), mos_labels(scan, r.dynamic));
    if (seq.image_width > 0) {
      write_label_mask(opt.out / "labels" / (scan.name + ".png"), to_input_order(scan, labels, kLabelUnscored),
                       seq.image_width, seq.image_height);
    }
    dynamic_cloud.add(scan, r.dynamic, r.score, r.index);
    static_cloud.add(scan, keep_static, r.score, r.index);

    nlohmann::json js{{"scan", scan.name},
                      {"points", scan.size()},
                      {"dynamic", n_dyn},
                      {"unscored", n_unscored},
                      {"window", {r.scans_before, r.scans_after}},
                      {"full_window", r.scans_before == cfg.scorer.window_half &&
                                          r.scans_after == cfg.scorer.window_half},
                      {"voxel_size", r.voxel_size},
                      {"downsampled", r.downsampled},
                      {"dynamic_downsampled_before_completion", r.dynamic_before_completion},
                      {"dynamic_downsampled", r.dynamic_downsampled},
                      {"tracked_points", r.tracked_points},
                      {"scoring_seconds", r.seconds}};
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
  };

  // Four stages run concurrently on consecutive scans (TBB pipeline, each stage in order):
  // read + pose, scoring, mapping, writing. Each stage owns its state.
  struct Item {
    std::size_t index = 0;
    bool flush = false;  // after the log: carries one of the scans held at its end
    std::size_t flushes_after = 0;  // flush items still to come after this one
    Scan world;
    std::vector<std::uint32_t> labels;
    std::vector<std::pair<ScoredScan, std::vector<std::uint32_t>>> scored;
  };
  std::map<std::size_t, std::vector<std::uint32_t>> waiting;  // stage 2: labels of unscored scans
  double read_s = 0, odometry_s = 0, scoring_s = 0;
  std::size_t next = 0;
  auto attach = [&](std::vector<ScoredScan> ready, Item& item) {
    for (auto& r : ready) {
      auto labels = std::move(waiting[r.index]);
      waiting.erase(r.index);
      item.scored.emplace_back(std::move(r), std::move(labels));
    }
  };
  double visibility_s = 0;  // offline pass 1: counting each scan's hits
  std::deque<ScoredScan> held;  // stage 2: scans released at the log's end, not yet sent on
  std::size_t flushes_left = static_cast<std::size_t>(cfg.scorer.window_half) * (cfg.scorer.tracks.enabled ? 2 : 1);
  tbb::parallel_pipeline(
      4,
      tbb::make_filter<void, std::shared_ptr<Item>>(
          tbb::filter_mode::serial_in_order,
          [&](tbb::flow_control& fc) -> std::shared_ptr<Item> {
            if (next == seq.size()) {
              // The scans the scorer and the tracker still hold leave one item each, so that
              // mapping one overlaps writing the one before (in one item, all were mapped
              // first: 20 scans x 31 ms one after another on the 131k stream).
              if (flushes_left == 0) {
                fc.stop();
                return nullptr;
              }
              auto item = std::make_shared<Item>();
              item->flush = true;
              item->flushes_after = --flushes_left;
              return item;
            }
            auto item = std::make_shared<Item>();
            item->index = next++;
            auto t = Clock::now();
            LoadedScan loaded = load_scan(seq, item->index);
            dropped += loaded.dropped_non_finite;
            if (loaded.scan.size() == 0) note_empty(loaded, empty_scans);
            masked += drop_masked(loaded, mask);
            item->labels = std::move(loaded.labels);
            read_s += since(t);
            t = Clock::now();
            if (odom) {
              std::lock_guard<std::mutex> lock(odom_mutex);
              if (item->index == 0 && cfg.odometry.level_first_scan) {
                if (const auto r = level_rotation(loaded.scan.points)) level.linear() = *r;
                else std::fprintf(stderr, "%s: level_first_scan: no dominant plane in the first scan; frame kept\n", opt.command.c_str());
              }
              auto step = odom->register_scan(loaded.scan);
              step.pose = level * step.pose;
              item->world = std::move(step.deskewed);
              item->world.points = (step.pose.cast<float>() * item->world.points).eval();
              item->world.pose = step.pose;
              poses.push_back({loaded.scan.stamp + step.reference_offset, step.pose});
              // Odometry keeps the returns within its range limits: the labels follow them (they
              // had stayed in the loaded order, and every label after the first dropped point
              // counted against the wrong point in summary.json's metrics).
              item->labels = follow_points(loaded.scan, item->labels, item->world);
            } else if (seq.world_frame) {
              poses.push_back({loaded.scan.stamp, *loaded.scan.pose});
              item->world = std::move(loaded.scan);
            } else {
              item->world = to_world(loaded.scan, sweep_motion(seq.poses, seq.times, item->index));
              poses.push_back({loaded.scan.stamp, seq.poses[item->index]});
            }
            odometry_s += since(t);
            throw_if_interrupted("reading scan " + std::to_string(item->index + 1) + " of " + std::to_string(seq.size()));
            return item;
          }) &
          tbb::make_filter<std::shared_ptr<Item>, std::shared_ptr<Item>>(
              tbb::filter_mode::serial_in_order,
              [&](std::shared_ptr<Item> item) {
                if (item->flush) {  // one held scan, or all that are left with the last flush
                  std::vector<ScoredScan> one;
                  while (!held.empty() && (one.empty() || item->flushes_after == 0)) {
                    one.push_back(std::move(held.front()));
                    held.pop_front();
                  }
                  attach(std::move(one), *item);
                  return item;
                }
                const auto t = Clock::now();
                waiting[item->index] = std::move(item->labels);
                // Scorer, then tracker; at the log's end both hand over what they hold.
                const bool last = item->index + 1 == seq.size();
                auto scored = scorer.push(std::move(item->world));
                if (last) append(scored, scorer.finish());
                std::vector<ScoredScan> ready;
                for (auto& s : scored) append(ready, tracker.push(std::move(s)));
                if (last) append(ready, tracker.finish());
                if (last && ready.size() > 1) {  // the rest leaves with the flush items
                  std::move(ready.begin() + 1, ready.end(), std::back_inserter(held));
                  ready.resize(1);
                }
                attach(std::move(ready), *item);
                scoring_s += since(t);
                return item;
              }) &
          tbb::make_filter<std::shared_ptr<Item>, std::shared_ptr<Item>>(
              tbb::filter_mode::serial_in_order,
              [&](std::shared_ptr<Item> item) {
                for (auto& [r, labels] : item->scored) {
                  if (!offline) {
                    map_scan(r);
                    continue;
                  }
                  const auto t = Clock::now();
                  visibility->add_hits(r.scan.points);
                  visibility_s += since(t);
                }
                return item;
              }) &
          tbb::make_filter<std::shared_ptr<Item>, void>(
              tbb::filter_mode::serial_in_order, [&](std::shared_ptr<Item> item) {
                for (auto& [r, labels] : item->scored) {
                  if (offline) {
                    feed_back(r);
                    write_spill(spill_dir / (scan_name(r.index) + ".spill"), r, labels);
                  } else {
                    write_scan(r, labels);
                  }
                  // Counts scans through the last stage: the first stage ran a window ahead
                  // ("30/30 scans, ETA 0 s" while 10 were still being scored).
                  progress.update(++scans_done);
                }
                if (!item->scored.empty() && !item->flush) finished_at.push_back(Clock::now());
              }));
  progress.finish();
  if (offline) {
    const auto pass = run_offline_pass(opt.command, seq.size(), spill_dir, *visibility, cfg, map_scan, write_scan);
    void_added = pass.added;
    void_vetoed = pass.vetoed;
    stage_seconds["visibility"] = visibility_s + pass.rays_seconds;
    stage_seconds["judging"] = pass.judging_seconds;
  }
  stage_seconds["mapping"] = mapping_s;
  stage_seconds["write"] = write_s;
  stage_seconds["read"] = read_s;
  stage_seconds["odometry"] = odometry_s;
  stage_seconds["scoring"] = scoring_s;

  if (points == 0) {
    fail(opt.input, "no valid point in any of its " + std::to_string(seq.size()) +
                        " scans (empty, or only NaN / infinite coordinates): nothing to score or map");
  }
  auto t = Clock::now();
  // The map files are independent of each other: written side by side, but the large clouds
  // one after another (each write converts a whole cloud for PCL: two at once doubled the peak
  // memory), and the OctoMap ones in order (writing the .bt prunes the tree). An error in any
  // task is rethrown here.
  tbb::parallel_invoke(
      [&] { dynamic_cloud.write(opt.out / (opt.mapping ? "map_dynamic.pcd" : "dynamic.pcd")); },
      [&] {
        static_cloud.write(opt.out / (opt.mapping ? "map_static.pcd" : "static.pcd"));
        if (opt.mapping) static_cloud.write(opt.out / "map_static.ply");
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
  if (opt.mapping) summary["octomap_leaves"] = octo->leaf_count();
  if (use_odometry) {
    write_pose_files(opt.out, poses, seq.calib_tr);
    summary["pose_files"] = pose_files_json(seq.calib_tr, poses.empty() ? 0.0 : poses.front().stamp - seq.times.front());
  }
  stage_seconds["write"] += since(t);

  const double seconds = progress.elapsed_s();
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
                             {"vetoed_points", void_vetoed}};
  }
  summary["tracked_points"] = tracked;
  summary["non_finite_dropped"] = dropped;
  summary["empty_scans"] = empty_scans;
  summary["platform_mask"] = {{"masked_points", masked}, {"learnt_cells", mask.cells.size()},
                              {"crop_box", !mask.crop_box.empty()}, {"note", mask.note}};
  summary["seconds"] = seconds;
  summary["scans_per_second"] = seconds > 0 ? static_cast<double>(seq.size()) / seconds : 0.0;
  summary["stage_seconds"] = stage_seconds;
  // The rate a live sensor would see: input scans through the whole pipeline per second in
  // the steady state, from the first scan that released output to the one before the last
  // (the scorer's first full window releases N scans at once; after the last scan, the held
  // scans leave one flush item each, not counted). Counting outputs up to the last N instead
  // had read 22 scans/s as 28 without the tracker and as 16 with it.
  if (!offline && finished_at.size() >= 3) {
    const double span = std::chrono::duration<double>(finished_at[finished_at.size() - 2] - finished_at[0]).count();
    summary["sustained_scans_per_second"] = span > 0 ? static_cast<double>(finished_at.size() - 2) / span : 0.0;
  }
  summary["per_scan"] = per_scan;
  if (seq.has_labels()) summary["moving"] = metrics_json(total);
  write_summary(opt.out, summary, true);

  std::printf("%s: %zu scans, %zu of %zu points dynamic (%.1f scans/s)\n", opt.command.c_str(),
              seq.size(), dynamic_points, points, seq.size() / std::max(seconds, 1e-9));
  if (seq.has_labels()) {
    std::printf("  moving class vs labels: IoU %.3f  precision %.3f  recall %.3f\n", total.iou(),
                total.precision(), total.recall());
  }
  std::printf("  outputs in %s:", opt.out.c_str());
  if (opt.mapping) std::printf(" map.bt map.ot map_static.pcd map_static.ply map_dynamic.pcd");
  else std::printf(" static.pcd dynamic.pcd");
  if (use_odometry) std::printf(" poses_kitti.txt poses_tum.txt");
  std::printf(" scores/ labels/ summary.json\n");
  if (!mos_dir.empty()) std::printf("  SemanticKITTI MOS predictions in %s\n", mos_dir.c_str());
}

}  // namespace cleanmap::app
