#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/free_space_vote.hpp"
#include "mapping/visibility_map.hpp"

namespace cleanmap {

struct WholeLogVerdict {
  std::size_t added = 0;   // points made dynamic by what the log saw through
  std::size_t vetoed = 0;  // points the normals called dynamic that the log saw stand
};

// An offline run's second opinion on one scan (world frame), given the whole log's visibility:
// - objects (clusters of non-ground points, `rule`) whose cells the log saw through more than
//   it saw them occupied are dynamic: what passes by, which normals miss when a car's side
//   slides within its own plane;
// - at the log's first and last scan (`log_end`) a dynamic object (cluster of dynamic points,
//   `rule.radius`) whose cells the log saw occupied more often than through is static again.
//   There the normals' window has one side only, and a surface coming into view looks to them
//   like one that appeared (SemanticKITTI 07's last scan: 450 points of a wall, its cells hit
//   in 2-3 scans, crossed in 0-3). Visibility tells the two apart: where something appeared,
//   the log saw through it before. Inside the log the normals have both sides, and an object
//   that crawls (its cells occupied most of the time) stays theirs to call, unless the log's
//   rays went through its cells in under one scan per 25 that hit them (Counts::through: a
//   ray within the margin of the hits may only have grazed them), counting only scans before
//   a cell's first hit or after its last (Counts::through_apart). A mover leaves the space it
//   held, and what comes closer was seen through before it arrived; a static fence or hedge is
//   hit by nearly every scan that sees it and let through now and then, between the scans
//   that hit it (whole_log_vote.cpp has the measured reason for 25).
//   Never gone through at all, first (the static synthetic log: 481 -> 268 false points,
//   building faces 50 m away at the scorer's threshold); bench/quality.sh: no set worse,
//   kitti00 0.483 -> 0.487, Pandar64 0.569 -> 0.573 (SA 96.85 -> 96.98), synthetic street
//   0.951 -> 0.952. Then under one per 25: Pandar64 0.561 -> 0.571 (precision 0.655 ->
//   0.668, SA 94.88 -> 95.05), the rest unchanged. Requiring fewer crossings than hits inside
//   the log as at its ends lost what crawls (SemanticKITTI 07 0.956 -> 0.684, Pandar64 DA 57
//   -> 27, before its deskewing). Then apart from the hits: kitti00 0.638 -> 0.744 (precision
//   0.649 -> 0.759), Pandar64 0.576 -> 0.579 (points/track 0.884 -> 0.890), the static
//   synthetic street on given poses 42 -> 0 false points (an angled car's corner cells,
//   grazed by rays of scans between those that hit them), every recall the same.
// - at the log's ends, an object holding a point of `on_moving_track` (per point, empty: none;
//   ScoredScan::on_moving_track) is judged as inside the log: its track was seen moving where
//   the normals had both sides. A car driving alongside hits the cells it leaves with its own
//   body scan after scan, so the log saw them occupied more often than crossed
//   (SemanticKITTI 04: 206 points of a car in the first scan and 478 of two in the last,
//   found by the normals and the tracker and then made static). A far static blob the
//   normals call moving inside the log, whose centroid jitters by the cluster radius, is a
//   confirmed track too, and what passes the rule inside the log there now passes at its ends
//   (KITTI 00: 47 points 65 m behind the sensor in scan 0, as in scans 1-8).
// Updates `dynamic` (1 = dynamic) in place.
WholeLogVerdict judge_with_log(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                               const VisibilityMap& log, const GroundQuery& ground_of,
                               const ObjectRule& rule, bool log_end, double voxel = 0.2,
                               const std::vector<std::uint8_t>& on_moving_track = {});

// judge_with_log's rule at the log's ends alone (no objects added), for an online run's first
// and last scan: there the normals' window has one side too, and `log` holds the scans at hand
// (the window's), which saw through a place something left and not through a wall that came
// into view. Returns the points made static.
std::size_t judge_log_end(const Eigen::Matrix3Xf& points, std::vector<std::uint8_t>& dynamic,
                          const VisibilityMap& log, const ObjectRule& rule, double voxel = 0.2,
                          const std::vector<std::uint8_t>& on_moving_track = {});

// Of `among` (indices of a scan's static points, world frame), those whose cell the whole log
// saw standing at least as often as gone through: rays went through its hits
// (Counts::through) in no more scans than hit it. Surfaces the clean map keeps occupied
// whatever its own rays did to them (OctoMapBuilder::pin). An OctoMap cell is crossed by every
// ray that passes within its 0.3 m, and a road's cells farther off, hit by a ring in one scan
// and missed by the next, are crossed by the rays to the road beyond: 4.8 % of SemanticKITTI
// 04's static truth lay in free cells of the clean map. The log's visibility cells know their
// hits' level, and a ray over the road is no ray through it. Cells gone through more often
// than hit are left to the OctoMap's own weighing: pinning every static point's cell kept
// trails of movers missed (SemanticKITTI 01's dynamic points alone in their cells 2.80 ->
// 3.94 % occupied). Pinning only cells never gone through, first, then these (bench/quality.sh,
// map table, static truth in occupied cells / dynamic points alone in occupied cells, %):
// SemanticKITTI 01 78.90 / 2.83 -> 79.88 / 2.90, 04 83.47 / 1.56 -> 84.17 / 1.61, 07 96.09 /
// 0 -> 96.23 / 0, Pandar64 points/track 88.76 / 0.52 -> 89.19 / 0.66: 8-24 k static points
// kept for 2-1000 points of trails. Pinning from every scan instead of every scan the map
// inserts (insert_every) kept three times the trails (SemanticKITTI 04 1.56 -> 4.54 %).
std::vector<std::int32_t> seen_standing(const VisibilityMap& log, const Eigen::Matrix3Xf& points,
                                        const std::vector<std::int32_t>& among);

}  // namespace cleanmap
