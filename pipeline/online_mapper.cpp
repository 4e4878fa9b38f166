#include "pipeline/online_mapper.hpp"

#include <cmath>
#include <utility>

#include "io/error.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/pipeline_run.hpp"

namespace cleanmap::pipeline {

OnlineMapper::OnlineMapper(PipelineConfig config) : config_(std::move(config)) {
  // The settings are checked now, as `run` checks them before its first scan.
  validate(config_.scorer);
  validate(config_.mapping.map);
  if (config_.mapping.free_space) validate(config_.mapping.free_space_objects, "mapping: free space vote");
  validate(config_.mapping.visibility);
  validate(config_.input.platform);
}

OnlineMapper::~OnlineMapper() = default;

void OnlineMapper::start(bool given_poses) {
  given_poses_ = given_poses;
  options_ = std::make_unique<PipelineOptions>();
  options_->command = "OnlineMapper";
  options_->odometry = !given_poses;
  options_->mapping = true;
  options_->offline = false;
  options_->streamed = true;
  options_->on_scan = [this](const ScoredScan& r, std::vector<std::uint32_t> labels, std::vector<float> scores) {
    Eigen::Isometry3d pose = r.scan.pose ? *r.scan.pose : Eigen::Isometry3d::Identity();
    pose.translation() += run_->seq.origin;  // back in the pushed poses' frame
    ready_.push_back({r.index, std::move(labels), std::move(scores), pose});
  };
  Sequence stream;
  stream.layout = "stream";
  stream.times_source = "pushed stamps";
  stream.poses_source = given_poses ? "pushed poses" : "";
  run_ = std::make_unique<PipelineRun>(*options_, config_, std::move(stream));
}

std::vector<MapperResult> OnlineMapper::push(Scan scan) {
  if (finished_) throw Error("OnlineMapper: push after finish()");
  const bool given = scan.pose.has_value();
  if (pushed_ == 0) start(given);
  if (given != given_poses_) {
    throw Error("OnlineMapper: scan " + std::to_string(pushed_) + (given ? " has a pose, the first had none" : " has no pose, the first had one") +
                ": give every scan a pose or none");
  }
  if (given && !scan.pose->matrix().allFinite()) throw Error("OnlineMapper: scan " + std::to_string(pushed_) + ": the pose is not finite");
  if (std::isnan(scan.stamp)) scan.stamp = static_cast<double>(pushed_) / config_.input.rate_hz;
  if (!std::isfinite(scan.stamp) || (pushed_ > 0 && !(scan.stamp > last_stamp_))) {
    throw Error("OnlineMapper: scan " + std::to_string(pushed_) + ": stamp " + std::to_string(scan.stamp) +
                " must be finite and after the one before (" + std::to_string(last_stamp_) + ")");
  }
  if (scan.time.size() != 0 && scan.time.size() != scan.points.cols()) {
    throw Error("OnlineMapper: scan " + std::to_string(pushed_) + ": " + std::to_string(scan.time.size()) +
                " times for " + std::to_string(scan.points.cols()) + " points");
  }
  last_stamp_ = scan.stamp;
  LoadedScan loaded;
  scan.name = scan_name(pushed_);
  scan.input_size = scan.size();
  const DroppedPoints dropped = drop_invalid(scan);
  loaded.dropped_non_finite = dropped.non_finite;
  loaded.dropped_out_of_range = dropped.out_of_range;
  loaded.scan = std::move(scan);
  if (given) {
    // As `run` does with given poses: a local origin near the first one (io/sequence.hpp).
    if (pushed_ == 0) run_->seq.origin = local_origin_near(loaded.scan.pose->translation());
    loaded.scan.pose->translation() -= run_->seq.origin;
    run_->seq.poses.push_back(*loaded.scan.pose);
  }
  run_->seq.times.push_back(loaded.scan.stamp);
  waiting_.push_back(std::move(loaded));
  ++pushed_;
  process(false);
  return std::exchange(ready_, {});
}

std::vector<MapperResult> OnlineMapper::finish() {
  if (finished_ || !run_) {
    finished_ = true;
    return {};
  }
  finished_ = true;
  process(true);
  if (posed_ == pushed_ && waiting_.empty() && !run_->scorer_finished) {
    // Every scan went through before the end was known: the scorer and tracker hand over
    // what they hold, as after a log's last scan.
    PipelineItem end;
    run_->release(end, {}, true);
    for (auto& [r, labels] : end.scored) {
      run_->map_scan(r);
      run_->write_scan(r, labels);
    }
  }
  PipelineItem rest;
  rest.flush = true;
  run_->flush(rest);  // flushes_after 0: everything held
  for (auto& [r, labels] : rest.scored) {
    run_->map_scan(r);
    run_->write_scan(r, labels);
  }
  return std::exchange(ready_, {});
}

void OnlineMapper::process(bool last) {
  const auto& platform = config_.input.platform;
  if (!mask_learnt_) {
    // As `run` learns it: from the first self_mask_scans scans, before any is posed.
    if (platform.automatic && waiting_.size() < static_cast<std::size_t>(platform.learn_scans) && !last) return;
    std::vector<Eigen::Matrix3Xf> first;
    for (std::size_t i = 0; platform.automatic && i < waiting_.size() && i < static_cast<std::size_t>(platform.learn_scans); ++i) {
      first.push_back(waiting_[i].scan.points);
    }
    run_->mask = learn_platform_mask(first, platform);
    mask_learnt_ = true;
  }
  while (!waiting_.empty()) {
    const bool has_next = waiting_.size() > 1;
    // The odometry primes scan 0 with scan 1; a given pose with per-point times needs the next
    // pose for the sweep's motion (the last scan continues the step before).
    if (!has_next && !last && !given_poses_ && posed_ == 0) break;
    if (!has_next && !last && given_poses_ && waiting_.front().scan.has_time()) break;
    LoadedScan loaded = std::move(waiting_.front());
    waiting_.pop_front();
    const LoadedScan* next = !given_poses_ && posed_ == 0 && !waiting_.empty() ? &waiting_.front() : nullptr;
    step(std::move(loaded), last && waiting_.empty(), next);
  }
}

void OnlineMapper::step(LoadedScan loaded, bool last, const LoadedScan* next) {
  auto item = run_->pose_scan(std::move(loaded), posed_++, last, next);
  run_->prepare(*item);
  run_->score(*item);
  if (last) run_->scorer_finished = true;
  for (auto& [r, labels] : item->scored) {
    run_->map_scan(r);
    run_->write_scan(r, labels);
  }
}

Eigen::Vector3d OnlineMapper::map_origin() const {
  return run_ ? run_->seq.origin : Eigen::Vector3d::Zero();
}

Eigen::Matrix3Xf OnlineMapper::static_points() const {
  return run_ ? run_->static_cloud.points() : Eigen::Matrix3Xf(3, 0);
}

}  // namespace cleanmap::pipeline
