#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <memory>

#include "dynamics/object_rule.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "io/pose_file.hpp"
#include "mapping/visibility_map.hpp"

namespace cleanmap::pipeline {

// An online run's first and last scan, judged as an offline run judges the log's ends
// (judge_log_end), with the scans the scorer looked at standing in for the log: the normals'
// window has one side there, and a wall coming into view looks to them like one that appeared
// (SemanticKITTI 07's last scan: 452 of the online run's 481 false points).
// Keeps the first `keep` scans' world-frame points until the first scan is judged (it leaves
// the scorer and tracker N or 2N scans after scan 2N came in), and always the last `keep`
// (the scorer's window, 2N+1).
class StreamEnds {
 private:
  struct Seen {
    std::size_t index = 0;
    Eigen::Matrix3Xf points;
    Eigen::VectorXf times;  // per point after `stamp`; empty without
    double stamp = 0.0;
    StampedPose pose;
  };
  using Scans = std::deque<std::shared_ptr<const Seen>>;  // a scan may be in both

 public:
  // The scans one end scan is judged with, as they were when it left the tracker: plain data,
  // so that the judging can run in a later stage than the planning (see plan()).
  struct Judgement {
    std::vector<Scans> with;  // the first scans, the last ones, or both (a short log)
  };

  explicit StreamEnds(std::size_t keep) : keep_(keep) {}
  std::size_t keep() const { return keep_; }
  // A scan as the scorer receives it (world frame), in the same order (the n-th call is
  // ScoredScan::index n), with its entry of the run's poses; one without a pose is left out.
  void add(const Scan& world, const StampedPose& pose);
  // What `r` is to be judged with: the first scan (scans_before 0) with the first scans, the
  // last (scans_after 0) with the last ones; nothing unless those include it. Planning the
  // first scan lets the first scans go. Called in scan order, in the stage that calls add().
  Judgement plan(const ScoredScan& r);
  // Points of `r` made static by its judgement. Reads only `j` and the settings: it may run in
  // another stage than add() and plan() (an online run's mapping stage, beside the scoring of
  // the scans after: judging the street's first and last scan took 0.8 and 0.5 s of the
  // scoring stage, which every other stage waits for).
  static std::size_t judge(ScoredScan& r, const Judgement& j, const VisibilityConfig& config, const ObjectRule& rule,
                           double voxel);

 private:
  static std::size_t judge_with(ScoredScan& r, const Scans& scans, const VisibilityConfig& config,
                                const ObjectRule& rule, double voxel);
  std::size_t keep_;
  Scans first_, recent_;
  bool first_done_ = false;
  std::size_t added_ = 0;
};

}  // namespace cleanmap::pipeline
