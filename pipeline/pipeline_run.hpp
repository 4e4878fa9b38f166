#pragma once

// The state of one `run` / `score` and its stages (private to apps/pipeline*.cpp). Each stage
// is a method; the TBB pipeline (pipeline.cpp) calls them in order, one stage per scan at a
// time, so each member below is touched by one stage only unless its comment says otherwise.

#include <Eigen/Geometry>
#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/pipeline.hpp"
#include "pipeline/run_inputs.hpp"
#include "pipeline/stream_ends.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "dynamics/object_tracker.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "evaluation/dynamic_metrics.hpp"
#include "io/sequence.hpp"
#include "mapping/octomap_builder.hpp"
#include "mapping/point_cloud_map.hpp"
#include "mapping/visibility_map.hpp"
#include "odometry/lidar_odometry.hpp"

namespace cleanmap::pipeline {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The visibility map's settings: it weighs hits and misses as the OctoMap does.
VisibilityConfig visibility_config(const PipelineConfig& cfg);

// One scan (or, after the log, one of the scans the scorer and tracker still hold) on its way
// through the five stages.
struct PipelineItem {
  std::size_t index = 0;
  bool flush = false;             // after the log: carries one of the scans held at its end
  bool last = false;              // the log's last scan
  std::size_t flushes_after = 0;  // flush items still to come after this one
  Scan world;
  PreparedScan prepared;  // `world`, prepared for the scorer (stage 2)
  StampedPose stamped;  // its entry of the run's poses (stage 1 writes it, stage 2 reads it)
  std::vector<std::uint32_t> labels;
  std::vector<std::pair<ScoredScan, std::vector<std::uint32_t>>> scored;
};

// Scans in the first pass's stages at once, online and offline (pipeline.cpp explains them).
inline constexpr std::size_t kScansInFlightOnline = 8, kScansInFlightOffline = 5;
inline std::size_t scans_in_flight(bool offline) { return offline ? kScansInFlightOffline : kScansInFlightOnline; }

struct PipelineRun {
  PipelineRun(const PipelineOptions& options, const PipelineConfig& config);
  // A run over `sequence` as given (OnlineMapper: an empty one that its pushes fill in).
  PipelineRun(const PipelineOptions& options, const PipelineConfig& config, Sequence sequence);

  // summary.json's description of the run, written before any scan.
  void describe(nlohmann::json& summary) const;
  // Stage 1: read scan `index`, mask the platform, pose it (odometry, given poses, VIEWPOINT).
  std::shared_ptr<PipelineItem> load(std::size_t index);
  // Scan `index` as read: from `early` when the platform mask read it, else from the input.
  LoadedScan take_scan(std::size_t index);
  // Stage 1 after reading: mask, then pose scan `index` (its entry of seq.poses / seq.times,
  // when given, must be there, and the next one's for a sweep with per-point times).
  // `next`: scan 1, to prime the odometry with at scan 0 (null: none).
  std::shared_ptr<PipelineItem> pose_scan(LoadedScan loaded, std::size_t index, bool last, const LoadedScan* next);
  // Stage 2: the scorer's preparation of the scan (downsampling, ground, its cells), beside
  // stage 3's scoring of the scan before it.
  void prepare(PipelineItem& item);
  // Stage 3: scorer then tracker; what they release joins the item with its labels.
  void score(PipelineItem& item);
  // What the scorer and tracker release after `scored` (the scorer's output for one scan) joins
  // `item` with its labels; `last`: the stream ended, they hand over what they hold.
  void release(PipelineItem& item, std::vector<ScoredScan> scored, bool last);
  void flush(PipelineItem& item);  // a flush item takes one held scan (the last, all left)
  // Stage 4: an online end scan's judgement (StreamEnds), the occupancy opinion, then the
  // static points into the map, rays cast from where the sensor was (`sensor`, known once the log's poses are: pass 2) or from the scan's pose.
  void map_scan(ScoredScan& r, const std::optional<SweepOrigin>& sensor = std::nullopt);
  // The scorer's dynamic points leave the odometry's local map (`exclude_dynamic`).
  void feed_back(const ScoredScan& r);
  // Stage 5: per-scan files, map clouds, metrics.
  void write_scan(ScoredScan& r, const std::vector<std::uint32_t>& gt);
  // After the passes: the map files, the pose files and the summary's figures.
  void write_maps();
  void summarise(nlohmann::json& summary, double seconds);

  const PipelineOptions& opt;
  const PipelineConfig& cfg;
  Sequence seq;  // OnlineMapper appends each pushed scan's time and pose
  const bool offline, use_odometry;
  const std::filesystem::path mos_dir, spill_dir;
  // The first scans_in_flight() of the scans the platform mask was learnt from (read before
  // `mask`), each taken by load(): reading the street's first 20 sweeps twice cost 0.3 s of its
  // 7.7 s online run. Only the first scans in flight are kept, as the pipeline holds that many
  // at its start anyway (the street's offline peak moves 30-60 MB between runs of one binary, so
  // keeping all 20, about 100 MB of sweeps, could not be told from it by /usr/bin/time).
  std::vector<std::optional<LoadedScan>> early;
  PlatformMask mask;  // OnlineMapper learns it from the first scans pushed

  std::unique_ptr<LidarOdometry> odom;
  // Map cells of static points the log saw standing (seen_standing), raised to occupied at the
  // end (offline).
  std::size_t cells_pinned = 0;
  // Bytes of the scans spilled between the passes (offline): the disk the run held at its peak.
  std::size_t spill_bytes = 0;
  std::mutex odom_mutex;  // stage 1 registers, stage 4 (online) or pass 1 (offline) feeds back
  // Scan 1 as read, to prime the odometry at scan 0: kept for load(1), so that it is read once.
  std::optional<LoadedScan> second;
  std::unique_ptr<OctoMapBuilder> octo;
  std::unique_ptr<VisibilityMap> visibility;
  LogFloor floor;  // offline: the whole log's lowest points, for pass 2's ground
  std::unique_ptr<StreamEnds> ends;  // online: the first and last scan's judge (planned in stage 3)
  // The end scans' judgements, by scan index: stage 3 (release) plans them, stage 4 (map_scan)
  // judges and removes them.
  std::map<std::size_t, StreamEnds::Judgement> judgements;
  std::mutex judgements_mutex;
  SpatiotemporalScorer scorer;
  ObjectTracker tracker;
  std::map<std::size_t, std::vector<std::uint32_t>> waiting;  // stage 2: labels of unscored scans
  std::deque<ScoredScan> held;  // stage 2: scans released at the log's end, not yet sent on
  bool scorer_finished = false;  // OnlineMapper: the last scan has been scored
  PointCloudMap dynamic_cloud, static_cloud, raw_cloud;

  std::vector<StampedPose> poses;
  MovingConfusion total;
  nlohmann::json per_scan = nlohmann::json::array();
  nlohmann::json empty_scans = nlohmann::json::array();  // {scan, reason} of scans with no valid point
  std::size_t masked = 0, points = 0, dynamic_points = 0, unscored = 0, dropped = 0, out_of_range = 0,
              viewpoints_missing = 0, free_space_added = 0,
              tracked = 0, void_added = 0, void_vetoed = 0, ends_vetoed = 0;
  // Busy time of each stage (they overlap: the sum exceeds the wall time).
  double read_s = 0, odometry_s = 0, preparing_s = 0, scoring_s = 0, mapping_s = 0, write_s = 0,
         visibility_s = 0, rays_s = 0, judging_s = 0;
  std::vector<Clock::time_point> finished_at;  // when each input scan that released output was written
  // Online latency: when each scan's reading began (stage 1) and how long until its labels were
  // written (stage 4), input order. Stage 1 appends, stage 4 reads an entry already written.
  std::deque<Clock::time_point> loaded_at;
  std::mutex loaded_mutex;
  std::vector<double> latency;
};

}  // namespace cleanmap::pipeline
