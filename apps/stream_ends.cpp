#include "apps/stream_ends.hpp"

#include <algorithm>

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
  // Hits of every scan first, then their rays, in the same order (VisibilityMap numbers them).
  VisibilityMap log(config);
  for (const auto& s : recent_) log.add_hits(s.points, s.origin);
  for (const auto& s : recent_) log.add_rays(s.points, s.origin);
  return judge_log_end(r.scan.points, r.dynamic, log, rule, voxel, r.on_moving_track);
}

}  // namespace cleanmap::app
