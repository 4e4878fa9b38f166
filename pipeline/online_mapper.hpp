#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "io/scan.hpp"
#include "pipeline/settings.hpp"

namespace cleanmap::pipeline {

struct PipelineRun;
struct PipelineOptions;

// One scan whose labels and scores are final: its place in the stream, per-point labels
// (the label files' codes: 251 moving, 9 static, 0 not scored) and scores, both one per point
// pushed, and the pose it was placed with.
struct MapperResult {
  std::size_t index = 0;
  std::vector<std::uint32_t> labels;
  std::vector<float> scores;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

// `cleanmap run --online` as a library: push one scan at a time (sensor frame, optional
// per-point times and pose), get back the scans whose decisions are final, after the window's
// delay (N scans, and N more with tracking). With poses pushed it is `run --online
// --use-given-poses` (labels equal, scan for scan); without, the odometry poses each scan.
// The first push decides which; every later one must do the same.
//
// What holds scans back beyond the window, so that the stream equals the run on the same log:
// the platform mask learns from the first self_mask_scans scans before any is scored; the
// odometry primes scan 0 with scan 1; a pushed pose with per-point times waits for the next
// pose (the sweep's motion).
class OnlineMapper {
 public:
  explicit OnlineMapper(PipelineConfig config);
  ~OnlineMapper();
  OnlineMapper(const OnlineMapper&) = delete;
  OnlineMapper& operator=(const OnlineMapper&) = delete;

  // `scan.stamp` NaN: index / rate_hz. Throws Error on a pose given after none was (or the
  // reverse), a non-finite pose, or a stamp not after the one before.
  std::vector<MapperResult> push(Scan scan);
  // The end of the stream: every scan still held.
  std::vector<MapperResult> finish();
  // The map's static points so far (the static cloud's voxel filter), relative to map_origin().
  Eigen::Matrix3Xf static_points() const;
  // The map's local origin in the pushed poses' frame: the first pose rounded to the kilometre
  // (zero without poses). Results' poses are in the pushed frame.
  Eigen::Vector3d map_origin() const;
  std::size_t scans_pushed() const { return pushed_; }

 private:
  void start(bool given_poses);
  void process(bool last);
  void step(LoadedScan loaded, bool last, const LoadedScan* next);

  PipelineConfig config_;
  std::unique_ptr<PipelineOptions> options_;
  std::unique_ptr<PipelineRun> run_;
  std::deque<LoadedScan> waiting_;  // pushed, not yet posed
  std::vector<MapperResult> ready_;
  std::size_t pushed_ = 0, posed_ = 0;
  bool given_poses_ = false, mask_learnt_ = false, finished_ = false;
  double last_stamp_ = 0.0;
};

}  // namespace cleanmap::pipeline
