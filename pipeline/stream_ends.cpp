#include "pipeline/stream_ends.hpp"

#include <algorithm>

#include "mapping/sweep_origin.hpp"
#include "mapping/visibility_around.hpp"
#include "mapping/whole_log_vote.hpp"

namespace cleanmap::pipeline {

void StreamEnds::add(const Scan& world, const StampedPose& pose) {
  const std::size_t index = added_++;
  if (keep_ == 0 || !world.pose || world.size() == 0) return;
  auto seen = std::make_shared<const Seen>(
      Seen{index, world.points, world.has_time() ? world.time : Eigen::VectorXf(), world.stamp, pose});
  if (!first_done_ && index < keep_) first_.push_back(seen);
  if (recent_.size() == keep_) recent_.pop_front();
  recent_.push_back(std::move(seen));
}

StreamEnds::Judgement StreamEnds::plan(const ScoredScan& r) {
  Judgement j;
  if (r.scans_before == 0) {
    j.with.push_back(first_);
    first_done_ = true;
    first_.clear();
  }
  if (r.scans_after == 0) j.with.push_back(recent_);
  return j;
}

std::size_t StreamEnds::judge(ScoredScan& r, const Judgement& j, const VisibilityConfig& config,
                              const ObjectRule& rule, double voxel) {
  std::size_t vetoed = 0;
  for (const auto& scans : j.with) vetoed += judge_with(r, scans, config, rule, voxel);
  return vetoed;
}

std::size_t StreamEnds::judge_with(ScoredScan& r, const Scans& scans, const VisibilityConfig& config,
                                   const ObjectRule& rule, double voxel) {
  const auto has = [&](const std::shared_ptr<const Seen>& s) { return s->index == r.index; };
  if (r.scan.size() == 0 || std::none_of(scans.begin(), scans.end(), has)) return 0;
  // Only the dynamic points can be vetoed: the scans' hits and rays around them.
  std::vector<Eigen::Index> dynamic;
  for (std::size_t i = 0; i < r.dynamic.size(); ++i) {
    if (r.dynamic[i]) dynamic.push_back(static_cast<Eigen::Index>(i));
  }
  if (dynamic.empty()) return 0;
  // Each ray from where the sensor was when it fired, as pass 2 casts them (SweepOrigin).
  std::vector<StampedPose> poses;
  for (const auto& s : scans) poses.push_back(s->pose);
  std::vector<ScanView> views;
  for (std::size_t j = 0; j < scans.size(); ++j) {
    const Seen& s = *scans[j];
    views.push_back({&s.points, &s.times, s.pose.pose.translation(), sweep_origin(poses, j, s.stamp)});
  }
  const VisibilityMap log = visibility_around(r.scan.points(Eigen::all, dynamic), views, config);
  return judge_log_end(r.scan.points, r.dynamic, log, rule, voxel, r.on_moving_track);
}

}  // namespace cleanmap::pipeline
