#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <deque>

#include "dynamics/object_rule.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "mapping/visibility_map.hpp"

namespace cleanmap::app {

// An online run's first and last scan, judged as an offline run judges the log's ends
// (judge_log_end), with the scans the scorer and tracker looked at standing in for the log:
// the normals' window has one side there, and a wall coming into view looks to them like one
// that appeared (SemanticKITTI 07's last scan: 452 of the online run's 481 false points).
// Keeps the last `keep` scans' world-frame points (the scorer's 2N+1: as many as its window).
class StreamEnds {
 public:
  explicit StreamEnds(std::size_t keep) : keep_(keep) {}
  // A scan as the scorer receives it (world frame), in the same order (the n-th call is
  // ScoredScan::index n); one without a pose is left out.
  void add(const Scan& world);
  // Points of `r` (the first or the last scan) made static; none unless the scans at hand
  // include it.
  std::size_t judge(ScoredScan& r, const VisibilityConfig& config, const ObjectRule& rule,
                    double voxel) const;

 private:
  struct Seen {
    std::size_t index = 0;
    Eigen::Matrix3Xf points;
    Eigen::Vector3d origin;
  };
  std::size_t keep_;
  std::deque<Seen> recent_;
  std::size_t added_ = 0;
};

}  // namespace cleanmap::app
