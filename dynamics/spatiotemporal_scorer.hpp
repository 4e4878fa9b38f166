#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dynamics/scan_objects.hpp"
#include "dynamics/scorer_config.hpp"
#include "io/scan.hpp"

namespace cleanmap {

// One scan's result: every full-resolution point scored and labelled.
struct ScoredScan {
  std::size_t index = 0;              // order in which the scan was pushed
  Scan scan;                          // as pushed: world frame, full resolution
  std::vector<float> score;           // per point, in [0, 1]; NaN = not scored
  std::vector<std::uint8_t> dynamic;  // per point, 1 = dynamic
  int scans_before = 0;               // window actually used: scans before and after this one
  int scans_after = 0;                // (N each in steady state; fewer at the log's ends)
  double voxel_size = 0.0;            // d_v used for this scan
  std::size_t downsampled = 0;        // points of this scan after voxel downsampling
  std::size_t scored_downsampled = 0; // ... of which had enough neighbours
  std::size_t dynamic_before_completion = 0;  // downsampled points over the threshold
  std::size_t dynamic_downsampled = 0;        // ... after object-level completion
  double seconds = 0.0;               // time spent scoring and upsampling this scan
  ScanObjects objects;                // for the ObjectTracker (empty when tracking is off)
  std::size_t tracked_points = 0;     // full points the tracker made dynamic
  // At the log's ends only (scans_before or scans_after 0; empty elsewhere and without the
  // tracker): 1 per full point on an object whose track the tracker saw moving from scans with
  // both sides of the window (ObjectTracker), which an offline run's pass 2 then judges by the
  // rule inside the log rather than the log-end one (judge_with_log).
  std::vector<std::uint8_t> on_moving_track;
};

struct WindowScan;  // a scan reduced to what its window needs (spatiotemporal_scorer.cpp)

// A scan prepared for the window (SpatiotemporalScorer::prepare): downsampled, its ground
// found and its cells' statistics summed, not yet in the window.
struct PreparedScan {
  std::shared_ptr<WindowScan> data;
  const Scan& scan() const;  // as given to prepare
};

// Streaming spatiotemporal-normal scorer (Falque, Le Gentil, Sukkar, ACRA 2023) over a sliding
// window of 2N+1 registered scans. Scan i is scored once scan i+N has been pushed, so results
// come out N scans late; the first N+1 scans wait for scan 2N (a one-sided window of full
// length), and finish() scores the last N with the last 2N+1 scans (all of a shorter log).
class SpatiotemporalScorer {
 public:
  explicit SpatiotemporalScorer(const ScorerConfig& config);
  ~SpatiotemporalScorer();
  SpatiotemporalScorer(SpatiotemporalScorer&&) noexcept;
  SpatiotemporalScorer& operator=(SpatiotemporalScorer&&) noexcept;

  // `scan`: points in the world frame (already placed with their own poses), per-point time
  // relative to `stamp` if known (else every point is at `stamp`). Returns the scans whose
  // scores became final (zero or one).
  std::vector<ScoredScan> push(Scan scan);

  // push() in two steps, so that a pipeline can prepare one scan (downsampling, ground, its
  // cells' statistics: a third of the scorer's time on the Pandar64 street) while the scan
  // before it is scored. prepare() must see the scans in push order, and may run in another
  // thread than push() at the same time (they share only the configuration).
  PreparedScan prepare(Scan scan);
  std::vector<ScoredScan> push(PreparedScan scan);

  // Scores every scan still waiting for its future neighbours. The scorer is empty afterwards.
  std::vector<ScoredScan> finish();

  // Fast mode: largest absolute difference between the incrementally kept per-cell statistics
  // and a recomputation from the scans now in the window (0 in exact arithmetic).
  double fast_statistics_drift() const;
  std::size_t window_size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cleanmap
