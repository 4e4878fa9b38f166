#include "apps/stream_ends.hpp"

#include <algorithm>

#include "mapping/visibility_around.hpp"
#include "mapping/whole_log_vote.hpp"

namespace cleanmap::app {

void StreamEnds::add(const Scan& world) {
  const std::size_t index = added_++;
  if (keep_ == 0 || !world.pose || world.size() == 0) return;
  if (recent_.size() == keep_) recent_.pop_front();
  recent_.push_back({index, world.points, world.pose->translation()});
}

std::size_t StreamEnds::judge(ScoredScan& r, const VisibilityConfig& config, const ObjectRule& rule,
                              double voxel) const {
  const auto has = [&](const Seen& s) { return s.index == r.index; };
  if (r.scan.size() == 0 || std::none_of(recent_.begin(), recent_.end(), has)) return 0;
  // Only the dynamic points can be vetoed: the scans' hits and rays around them.
  std::vector<Eigen::Index> dynamic;
  for (std::size_t i = 0; i < r.dynamic.size(); ++i) {
    if (r.dynamic[i]) dynamic.push_back(static_cast<Eigen::Index>(i));
  }
  if (dynamic.empty()) return 0;
  std::vector<ScanView> views;
  for (const auto& s : recent_) views.push_back({&s.points, s.origin});
  const VisibilityMap log = visibility_around(r.scan.points(Eigen::all, dynamic), views, config);
  return judge_log_end(r.scan.points, r.dynamic, log, rule, voxel, r.on_moving_track);
}

}  // namespace cleanmap::app
