#include "pipeline/offline_pass.hpp"

#include <chrono>
#include <memory>
#include <mutex>

#include "pipeline/offline_spill.hpp"
#include "pipeline/pipeline_stage.hpp"
#include "pipeline/progress.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "mapping/whole_log_vote.hpp"

namespace cleanmap::pipeline {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

fs::path spill_file(const fs::path& dir, std::size_t i) { return dir / (scan_name(i) + ".spill"); }

// Where scan i's sensor was over its sweep, where the log's poses say it moved (one per scan);
// at the scan's pose otherwise. Only for a posed scan.
SweepOrigin sensor_of(const std::vector<StampedPose>& poses, std::size_t scans,
                      const ScoredScan& r) {
  return poses.size() == scans ? sweep_origin(poses, r.index, r.scan.stamp)
                               : SweepOrigin{r.scan.pose->translation()};
}

// The first stage of a sweep: spills 0..scans-1 in order, each deleted once read when
// `consume` (the last sweep).
auto spill_source(const fs::path& dir, std::size_t scans, std::size_t& next, bool consume, StageFailure& failure) {
  return guarded_filter<void, std::shared_ptr<SpilledScan>>(
      tbb::filter_mode::serial_in_order, failure, [&dir, scans, &next, consume](tbb::flow_control& fc) {
        if (next == scans) {
          fc.stop();
          return std::shared_ptr<SpilledScan>();
        }
        const fs::path file = spill_file(dir, next++);
        auto s = std::make_shared<SpilledScan>(read_spill(file));
        if (consume) fs::remove(file);
        return s;
      });
}

}  // namespace

OfflinePassStats run_offline_pass(
    const std::string& command, std::size_t scans, const fs::path& spill_dir,
    VisibilityMap& visibility, const LogFloor& floor, const std::vector<StampedPose>& poses,
    const PipelineConfig& cfg,
    const std::function<void(ScoredScan&, const std::optional<SweepOrigin>&)>& map_scan,
    const std::function<void(ScoredScan&, const std::vector<std::uint32_t>&)>& write_scan) {
  OfflinePassStats stats;
  std::size_t rays_done = 0;
  // Every scan's rays, once every scan's hits are in (the spills hold the world-frame scans):
  // cast side by side, counted in order.
  visibility.fit_surfaces();
  Progress rays(command + " (rays)", scans);
  std::size_t next_ray = 0;
  std::mutex cast_time;
  // One record for both sweeps: a failure in the first is rethrown before the second starts.
  StageFailure failure;
  run_pipeline_stages(
      4, failure,
      spill_source(spill_dir, scans, next_ray, false, failure) &
          guarded_filter<std::shared_ptr<SpilledScan>, std::shared_ptr<VisibilityMap::ScanRays>>(
              tbb::filter_mode::parallel, failure,
              [&](std::shared_ptr<SpilledScan> s) {
                const auto t = Clock::now();
                const Scan& scan = s->scored.scan;
                auto cast = std::make_shared<VisibilityMap::ScanRays>();
                // Each ray from where the sensor was when it fired (SweepOrigin).
                if (scan.pose) {
                  const SweepOrigin sensor = sensor_of(poses, scans, s->scored);
                  *cast = visibility.cast(scan.points, scan.time, sensor);
                }
                std::lock_guard<std::mutex> lock(cast_time);
                stats.rays_seconds += since(t);
                return cast;
              }) &
          guarded_filter<std::shared_ptr<VisibilityMap::ScanRays>, void>(
              tbb::filter_mode::serial_in_order, failure, [&](std::shared_ptr<VisibilityMap::ScanRays> r) {
                const auto t = Clock::now();
                visibility.count(*r);
                std::lock_guard<std::mutex> lock(cast_time);  // the casts add theirs too
                stats.rays_seconds += since(t);
                rays.update(++rays_done);
              }));
  rays.finish();
  Progress pass2(command + " (pass 2 of 2)", scans);
  std::size_t next = 0;
  std::mutex judged;
  run_pipeline_stages(
      4, failure,
      spill_source(spill_dir, scans, next, true, failure) &
          guarded_filter<std::shared_ptr<SpilledScan>, std::shared_ptr<SpilledScan>>(
              tbb::filter_mode::parallel, failure,
              [&](std::shared_ptr<SpilledScan> s) {
                const auto t = Clock::now();
                ScoredScan& r = s->scored;
                const auto verdict = judge_with_log(
                    r.scan.points, r.dynamic, visibility,
                    [&](const Eigen::Matrix3Xf& sub) {
                      return segment_ground(sub, cfg.scorer.ground, floor);
                    },
                    cfg.mapping.free_space_objects, r.scans_before == 0 || r.scans_after == 0,
                    cfg.mapping.free_space_voxel, r.on_moving_track);
                std::lock_guard<std::mutex> lock(judged);
                stats.added += verdict.added;
                stats.vetoed += verdict.vetoed;
                stats.judging_seconds += since(t);
                return s;
              }) &
          guarded_filter<std::shared_ptr<SpilledScan>, std::shared_ptr<SpilledScan>>(
              tbb::filter_mode::serial_in_order, failure,
              [&](std::shared_ptr<SpilledScan> s) {
                std::optional<SweepOrigin> sensor;
                if (s->scored.scan.pose) sensor = sensor_of(poses, scans, s->scored);
                map_scan(s->scored, sensor);
                return s;
              }) &
          guarded_filter<std::shared_ptr<SpilledScan>, void>(
              tbb::filter_mode::serial_in_order, failure, [&](std::shared_ptr<SpilledScan> s) {
                write_scan(s->scored, s->labels);
                pass2.update(s->scored.index + 1);
              }));
  pass2.finish();
  return stats;
}

}  // namespace cleanmap::pipeline
