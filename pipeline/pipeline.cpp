#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <cstdio>
#include <iterator>

#include "pipeline/interrupt.hpp"
#include "pipeline/mos_layout.hpp"
#include "pipeline/offline_pass.hpp"
#include "pipeline/offline_spill.hpp"
#include "pipeline/output_dir.hpp"
#include "pipeline/pipeline_run.hpp"
#include "pipeline/pipeline_stage.hpp"
#include "pipeline/preset_yaml.hpp"
#include "pipeline/progress.hpp"
#include "pipeline/run_summary.hpp"
#include "io/error.hpp"
#include "odometry/deskew.hpp"

namespace cleanmap::pipeline {
namespace fs = std::filesystem;
namespace {

// Moves `more` onto the end of `into`.
void append(std::vector<ScoredScan>& into, std::vector<ScoredScan> more) {
  std::move(more.begin(), more.end(), std::back_inserter(into));
}

// The sequence, once every setting it depends on is known to be valid.
Sequence open_checked(const PipelineOptions& opt, const PipelineConfig& cfg) {
  validate(cfg.scorer);
  if (opt.mapping) validate(cfg.mapping.map);
  if (opt.mapping && cfg.mapping.free_space) validate(cfg.mapping.free_space_objects, "mapping: free space vote");
  if (opt.mapping) validate(cfg.mapping.visibility);  // offline: the log's; online: its ends
  // The 2D grid's height band (issue 45: an inverted band was accepted and gave an empty grid).
  if (opt.mapping && !(cfg.mapping.grid_z_min < cfg.mapping.grid_z_max)) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "--grid-z-min (mapping.grid_z_min) %g m must be below --grid-z-max %g m",
                  cfg.mapping.grid_z_min, cfg.mapping.grid_z_max);
    throw Error(msg);
  }
  validate(cfg.input.platform);
  const auto& origin = cfg.input.map_origin;
  // Within 1e8 m: the Earth's surface in any frame people georeference with (ECEF, UTM).
  if (!origin.empty() && (origin.size() != 3 || !(Eigen::Vector3d(origin[0], origin[1], origin[2]).cwiseAbs().maxCoeff() <= 1e8))) {
    throw Error("--map-origin (input.map_origin) takes 3 numbers within 1e8 m: x y z");
  }
  Sequence seq = open_sequence(opt.input, sequence_options(cfg.input));
  // Estimated poses start at the odometry's own origin: given ones (or world-frame scans) may
  // be georeferenced.
  const bool estimated = opt.odometry && !seq.world_frame;
  if (!origin.empty()) {
    set_local_origin(seq, Eigen::Vector3d(origin[0], origin[1], origin[2]));
  } else if (!estimated) {
    set_local_origin(seq, automatic_local_origin(seq));
  }
  if (!seq.origin.isZero()) {
    std::fprintf(stderr, "%s: map origin (%.3f, %.3f, %.3f) m in the poses' frame: the map files (map.bt, map.ot, "
                 "map_*.pcd/ply, map_2d) are relative to it (summary.json: map_origin)\n",
                 opt.command.c_str(), seq.origin.x(), seq.origin.y(), seq.origin.z());
  }
  return seq;
}


// Pass 1 (offline) or the only pass (online): five stages on consecutive scans at once (TBB
// pipeline, each stage in order): read + pose, the scorer's preparation, scoring, mapping
// (offline: the visibility map's hits), writing (offline: a spill per scan). Each stage owns
// its part of `run`. Preparing apart from scoring lets one scan's downsampling and ground run
// beside the scoring of the scan before it: scoring was the stage every other one waited for.
// Online, 8 scans in flight, not one per stage: an online run judges its first scan in the
// mapping stage (0.9 s on the Pandar64 street), and with five the scoring stage stopped for
// 0.5 s of it once the items behind it filled the pipeline (a temporary timeline of the
// stages). The cost: reading runs further ahead, so a scan waits longer from input to labels
// when the input comes faster than the pipeline (files; a live sensor at 10 Hz does not).
// Offline, 8 gave the same speed (0.998x) and a higher peak (the street: about +5 %): 5.
void first_pass(PipelineRun& run, Progress& progress) {
  std::size_t next = 0, scans_done = 0;
  const std::size_t n = run.seq.size();
  // One flush item per scan held at the end: never more than the log has.
  std::size_t flushes_left =
      std::min(n, static_cast<std::size_t>(run.cfg.scorer.window_half) * (run.cfg.scorer.tracks.enabled ? 2 : 1));
  StageFailure failure;
  run_pipeline_stages(
      scans_in_flight(run.offline), failure,
      guarded_filter<void, std::shared_ptr<PipelineItem>>(
          tbb::filter_mode::serial_in_order, failure,
          [&](tbb::flow_control& fc) -> std::shared_ptr<PipelineItem> {
            if (next < n) return run.load(next++);
            // The scans the scorer and the tracker still hold leave one item each, so that
            // mapping one overlaps writing the one before (in one item, all were mapped
            // first: 20 scans x 31 ms one after another on the 131k stream).
            if (flushes_left == 0) {
              fc.stop();
              return nullptr;
            }
            auto item = std::make_shared<PipelineItem>();
            item->flush = true;
            item->flushes_after = --flushes_left;
            return item;
          }) &
          guarded_filter<std::shared_ptr<PipelineItem>, std::shared_ptr<PipelineItem>>(
              tbb::filter_mode::serial_in_order, failure,
              [&](std::shared_ptr<PipelineItem> item) {
                if (!item->flush) run.prepare(*item);
                return item;
              }) &
          guarded_filter<std::shared_ptr<PipelineItem>, std::shared_ptr<PipelineItem>>(
              tbb::filter_mode::serial_in_order, failure,
              [&](std::shared_ptr<PipelineItem> item) {
                if (item->flush)
                  run.flush(*item);
                else
                  run.score(*item);
                return item;
              }) &
          guarded_filter<std::shared_ptr<PipelineItem>, std::shared_ptr<PipelineItem>>(
              tbb::filter_mode::serial_in_order, failure,
              [&](std::shared_ptr<PipelineItem> item) {
                for (auto& [r, labels] : item->scored) {
                  if (!run.offline) {
                    run.map_scan(r);
                    continue;
                  }
                  const auto t = Clock::now();
                  run.visibility->add_hits(
                      r.scan.points, r.scan.pose ? std::optional<Eigen::Vector3d>(r.scan.pose->translation()) : std::nullopt);
                  // The log's floor, for pass 2's ground (timed with the visibility map).
                  add_to_floor(r.scan.points, run.cfg.scorer.ground, run.floor);
                  run.visibility_s += since(t);
                }
                return item;
              }) &
          guarded_filter<std::shared_ptr<PipelineItem>, void>(
              tbb::filter_mode::serial_in_order, failure, [&](std::shared_ptr<PipelineItem> item) {
                for (auto& [r, labels] : item->scored) {
                  if (run.offline) {
                    run.feed_back(r);  // in pass 1, while odometry still runs: pass 2 comes after the last pose
                    run.spill_bytes +=
                        write_spill(run.spill_dir / (scan_name(r.index) + ".spill"), r, labels);
                    const std::size_t spilled = scans_done + 1;
                    check_spill_space(run.spill_dir, run.spill_bytes, spilled,
                                      run.seq.size() > spilled ? run.seq.size() - spilled : 0);
                  } else {
                    run.write_scan(r, labels);
                    std::lock_guard<std::mutex> lock(run.loaded_mutex);
                    run.latency.push_back(since(run.loaded_at[r.index]));
                  }
                  // Counts scans through the last stage: the first stage ran a window ahead
                  // ("30/30 scans, ETA 0 s" while 10 were still being scored).
                  progress.update(++scans_done);
                }
                if (!item->scored.empty() && !item->flush) run.finished_at.push_back(Clock::now());
              }));
}

}  // namespace

PipelineRun::PipelineRun(const PipelineOptions& options, const PipelineConfig& config)
    : PipelineRun(options, config, open_checked(options, config)) {}

PipelineRun::PipelineRun(const PipelineOptions& options, const PipelineConfig& config, Sequence sequence)
    : opt(options),
      cfg(config),
      seq(std::move(sequence)),
      offline(options.offline && options.mapping),
      // DynamicMap sequences are registered already: no odometry, and the output keeps every
      // raw input point that is not removed (never voxel centres or re-posed copies), as that
      // benchmark scores kept points by distance.
      use_odometry(options.odometry && !seq.world_frame),
      mos_dir(options.mos_predictions ? mos_predictions_dir(options.out, options.input, options.mos_sequence) : fs::path()),
      spill_dir(options.out / ".offline"),
      mask(platform_mask(seq, config.input.platform, &early, scans_in_flight(options.offline && options.mapping))),
      scorer(config.scorer),
      tracker(config.scorer.tracks, config.scorer.window_half, config.scorer.objects.radius,
              config.scorer.pose_noise, config.scorer.pose_noise_deg),
      dynamic_cloud(0.0),
      static_cloud(seq.world_frame ? 0.0 : options.mapping ? config.mapping.cloud_voxel : 0.05),
      raw_cloud(seq.world_frame ? 0.0 : options.mapping ? config.mapping.cloud_voxel : 0.05) {
  if (use_odometry) {
    validate(cfg.odometry);
    odom = std::make_unique<LidarOdometry>(cfg.odometry);
  }
  if (!use_odometry && !seq.has_poses() && !seq.world_frame && !opt.streamed) {
    fail(opt.input, "no poses: give --poses FILE or put poses.txt in the folder "
                    "(`cleanmap odometry` estimates them, `cleanmap run` does it itself)");
  }
  if (seq.world_frame && seq.has_poses()) {
    std::fprintf(stderr, "%s: the poses of %s replace the scans' VIEWPOINTs\n", opt.command.c_str(), seq.poses_source.c_str());
  }
  if (opt.mapping) octo = std::make_unique<OctoMapBuilder>(cfg.mapping.map);
  if (offline) visibility = std::make_unique<VisibilityMap>(visibility_config(cfg));
  if (!offline && opt.mapping)
    ends = std::make_unique<StreamEnds>(2 * static_cast<std::size_t>(cfg.scorer.window_half) + 1);
}

void PipelineRun::describe(nlohmann::json& summary) const {
  summary["command"] = opt.command;
  summary["input"] = opt.input.string();
  summary["layout"] = seq.layout;
  if (!mos_dir.empty()) summary["mos_predictions"] = mos_dir.string();
  summary["mode"] = offline ? "offline" : "online";
  summary["times"] = seq.times_source;
  // (issue 45: a poses.txt beside pcd/ replaced the VIEWPOINTs while this still said VIEWPOINT)
  summary["poses"] = use_odometry                         ? "odometry"
                     : seq.world_frame && seq.has_poses() ? seq.poses_source + " (instead of the files' VIEWPOINT)"
                     : seq.world_frame                    ? "VIEWPOINT (world-frame scans)"
                                                          : seq.poses_source;
  // world = map + map_origin: the map files' coordinates are relative to it.
  summary["map_origin"] = {seq.origin.x(), seq.origin.y(), seq.origin.z()};
  summary["input_settings"] = to_json(cfg.input, input_fields());
  summary["scorer"] = to_json(cfg.scorer, scorer_fields());
  if (use_odometry) summary["odometry"] = to_json(cfg.odometry, odometry_fields());
  if (opt.mapping) summary["mapping"] = to_json(cfg.mapping, mapping_fields());
  summary["libraries"] = library_versions();
}

LoadedScan PipelineRun::take_scan(std::size_t index) {
  if (index < early.size() && early[index]) {
    LoadedScan loaded = std::move(*early[index]);
    early[index].reset();
    return loaded;
  }
  return load_scan(seq, index);
}

std::shared_ptr<PipelineItem> PipelineRun::load(std::size_t index) {
  const auto t = Clock::now();
  {
    std::lock_guard<std::mutex> lock(loaded_mutex);
    loaded_at.push_back(t);
  }
  const bool primed = index == 1 && second.has_value();
  LoadedScan loaded = primed ? std::move(*second) : take_scan(index);
  if (primed) second.reset();
  read_s += since(t);
  // Scan 1 as read, to prime the odometry at scan 0: kept for load(1), so that it is read once.
  if (odom && index == 0 && seq.size() > 1) second = take_scan(1);
  return pose_scan(std::move(loaded), index, index + 1 == seq.size(), second ? &*second : nullptr);
}

std::shared_ptr<PipelineItem> PipelineRun::pose_scan(LoadedScan loaded, std::size_t index, bool last,
                                                     const LoadedScan* next) {
  auto item = std::make_shared<PipelineItem>();
  item->index = index;
  item->last = last;
  auto t = Clock::now();
  dropped += loaded.dropped_non_finite;
  out_of_range += loaded.dropped_out_of_range;
  if (loaded.viewpoint_missing && viewpoints_missing++ == 0) {
    std::fprintf(stderr, "%s: warning: scan %s has no VIEWPOINT (or the identity): it is placed at the frame's origin "
                 "and its rays cast from there (summary.json: viewpoint_missing_scans)\n", opt.command.c_str(),
                 loaded.scan.name.c_str());
  }
  if (loaded.scan.size() == 0) note_empty(loaded, empty_scans);
  masked += drop_masked(loaded, mask);
  item->labels = std::move(loaded.labels);
  read_s += since(t);
  t = Clock::now();
  if (odom) {
    std::lock_guard<std::mutex> lock(odom_mutex);
    if (index == 0 && next) {  // the first step, so that the first two sweeps are undistorted too
      LoadedScan after = *next;  // masked here; scan 1 is masked and counted as any other
      drop_masked(after, mask);
      odom->prime(loaded.scan, after.scan);
    }
    auto step = odom->register_scan(loaded.scan);
    if (index == 0 && !step.note.empty()) std::fprintf(stderr, "%s: first scan: %s\n", opt.command.c_str(), step.note.c_str());
    item->world = std::move(step.deskewed);
    item->world.points = (step.pose.cast<float>() * item->world.points).eval();
    item->world.pose = step.pose;
    poses.push_back({loaded.scan.stamp + step.reference_offset, step.pose});
    // Odometry keeps the returns within its range limits: the labels follow them (they had
    // stayed in the loaded order, and every label after the first dropped point counted
    // against the wrong point in summary.json's metrics).
    item->labels = follow_points(loaded.scan, item->labels, item->world);
  } else if (seq.world_frame) {
    poses.push_back({loaded.scan.stamp, *loaded.scan.pose});
    item->world = std::move(loaded.scan);
  } else {
    item->world = to_world(loaded.scan, sweep_motion(seq.poses, seq.times, index));
    poses.push_back({loaded.scan.stamp, seq.poses[index]});
  }
  item->stamped = poses.back();
  odometry_s += since(t);
  throw_if_interrupted("reading scan " + std::to_string(index + 1) + " of " + std::to_string(seq.size()));
  return item;
}

void PipelineRun::prepare(PipelineItem& item) {
  const auto t = Clock::now();
  item.prepared = scorer.prepare(std::move(item.world));
  preparing_s += since(t);
}

void PipelineRun::score(PipelineItem& item) {
  const auto t = Clock::now();
  waiting[item.index] = std::move(item.labels);
  if (ends) ends->add(item.prepared.scan(), item.stamped);
  release(item, scorer.push(std::move(item.prepared)), item.last);
  scoring_s += since(t);
}

void PipelineRun::release(PipelineItem& item, std::vector<ScoredScan> scored, bool last) {
  // Scorer, then tracker; at the log's end both hand over what they hold.
  if (last) append(scored, scorer.finish());
  std::vector<ScoredScan> ready;
  for (auto& s : scored) append(ready, tracker.push(std::move(s)));
  if (last) append(ready, tracker.finish());
  for (auto& r : ready) {  // the stream's first and last scan, judged in stage 4 (map_scan)
    if (!ends) break;
    auto j = ends->plan(r);
    if (j.with.empty()) continue;
    std::lock_guard<std::mutex> lock(judgements_mutex);
    judgements[r.index] = std::move(j);
  }
  if (last && ready.size() > 1) {  // the rest leaves with the flush items
    std::move(ready.begin() + 1, ready.end(), std::back_inserter(held));
    ready.resize(1);
  }
  for (auto& r : ready) {
    auto labels = std::move(waiting[r.index]);
    waiting.erase(r.index);
    item.scored.emplace_back(std::move(r), std::move(labels));
  }
}

void PipelineRun::flush(PipelineItem& item) {
  while (!held.empty() && (item.scored.empty() || item.flushes_after == 0)) {
    ScoredScan r = std::move(held.front());
    held.pop_front();
    auto labels = std::move(waiting[r.index]);
    waiting.erase(r.index);
    item.scored.emplace_back(std::move(r), std::move(labels));
  }
}

VisibilityConfig visibility_config(const PipelineConfig& cfg) {
  VisibilityConfig v = cfg.mapping.visibility;
  v.prob_hit = cfg.mapping.map.prob_hit;
  v.prob_miss = cfg.mapping.map.prob_miss;
  v.free_probability = cfg.mapping.map.free_probability;
  return v;
}

void run_pipeline(const PipelineOptions& opt, const PipelineConfig& cfg, nlohmann::json summary) {
  PipelineRun run(opt, cfg);
  make_dirs(opt.out / "scores");
  make_dirs(opt.out / "labels");
  if (!run.mos_dir.empty()) make_dirs(run.mos_dir);
  run.describe(summary);
  write_summary(opt.out, summary, false);
  write_preset(opt.out, cfg, kScorer | (run.use_odometry ? kOdometry : 0) |
                                 (opt.mapping ? kMapping : 0));
  if (!run.mask.note.empty()) {
    std::fprintf(stderr, "%s: platform mask: none learnt: %s\n", opt.command.c_str(), run.mask.note.c_str());
  }
  // The spills go whatever happens: a run stopped by bad input leaves no half of them behind.
  const RemovedAtExit spills(run.offline ? run.spill_dir : fs::path());
  if (run.offline) make_dirs(run.spill_dir);

  Progress progress(run.offline ? opt.command + " (pass 1 of 2)" : opt.command, run.seq.size());
  first_pass(run, progress);
  progress.finish();
  if (run.offline) {
    const auto pass = run_offline_pass(
        opt.command, run.seq.size(), run.spill_dir, *run.visibility, run.floor, run.poses, cfg,
        [&](ScoredScan& r, const std::optional<SweepOrigin>& sensor) { run.map_scan(r, sensor); },
        [&](ScoredScan& r, const std::vector<std::uint32_t>& gt) { run.write_scan(r, gt); });
    run.void_added = pass.added;
    run.void_vetoed = pass.vetoed;
    run.rays_s = pass.rays_seconds;
    run.judging_s = pass.judging_seconds;
  }
  if (run.points == 0) {
    fail(opt.input, "no valid point in any of its " + std::to_string(run.seq.size()) +
                        " scans (empty, or only NaN / infinite coordinates): nothing to score or map");
  }
  run.write_maps();
  run.summarise(summary, progress.elapsed_s());
}

}  // namespace cleanmap::pipeline
