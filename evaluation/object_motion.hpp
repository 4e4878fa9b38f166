#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <vector>

#include "evaluation/box_labels.hpp"
#include "io/scan.hpp"
#include "io/sequence.hpp"

namespace cleanmap {

// How far a labelled object moved, measured on its own points rather than on its hand-drawn
// box. Annotation tools draw boxes at key frames and interpolate between them: on the Pandar64
// street a parked truck's box (id 101) creeps 0.06 m a scan for ten scans and jumps back
// 0.6 m, so its 1 s line fit reads 0.5-0.7 m/s ("moving") in a third of the scans, while its
// points, registered 1 s apart, fit with 2-4 cm residuals at 0.02-0.1 m/s. A truck that brakes
// to a stop beside the sensor (id 100) had boxes that called it moving, standing, moving,
// standing and moving again; its points say 1.5-2 m/s, slowing, standing from scan 17 on.

// The world-frame points of each box of one scan (boxes grown by `margin` as the labels are),
// without the box's bottom `ground_band`: the road under a box's floor (and inside the
// margin) is no part of the object and stands still whatever it does.
// `sensor` and `world` are the same points (columns) in the sensor frame the boxes are drawn in
// and as placed in the world (per-point poses for a raw sweep: place_by_azimuth).
std::vector<Eigen::Matrix3Xf> points_in_boxes(const Eigen::Matrix3Xf& sensor, const Eigen::Matrix3Xf& world,
                                              const std::vector<LabelBox>& boxes, double margin = 0.1,
                                              double ground_band = 0.25);

struct ObjectShift {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // taking `from` onto `to`, m
  double residual = 0.0;  // median distance of `from`'s points to `to`'s after the shift, m
  // The two starts ended more than 0.1 m apart with residuals within 1 cm: a car's side slides
  // along itself, and its ends, the only faces that fix that motion, are too few to choose
  // (cars at 7 m/s on the Pandar64 street read as standing from the zero start).
  bool ambiguous = false;
};

// Horizontal-translation ICP, point to plane: each step pairs every point of `from` with its
// nearest in `to` and solves for the horizontal shift along the pairs' surface normals (from
// `to`'s neighbours), counting pairs within a reach that shrinks from 1 m to 0.1 m. Started
// from `guess`'s horizontal part and from no motion; the start that ends with the smaller
// residual wins. Height is left out: what boxes hold on a street (vehicles, people) moves along
// the ground, and little of what a low sensor sees of them faces up: on the Pandar64 street
// the height of a link between neighbouring scans wandered by up to 0.18 m (the box's floor
// band, which jitters with the box, cuts the sample) and summed to 0.6 m/s on a parked truck.
// Rotation is left out: over the 1 s it is measured on, a turning car turns a few degrees,
// and a poor fit is caught by the residual. nullopt when either side is empty.
std::optional<ObjectShift> register_object(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to,
                                           const Eigen::Vector3d& guess);

// What the object motion rule needs to trust a registration: enough points on both sides, and
// a fit as good as two samplings of one surface are (a point's nearest neighbour in another
// scan of the same surface lies within half the beam spacing: 7 cm at 40 m for a 0.2 deg
// lidar, plus 2-3 cm range noise).
struct ObjectMotionConfig {
  std::size_t min_points = 30;
  double max_residual = 0.1;  // m
};

// Per scan and box: the object's speed (m/s) over the window, from its own points: the
// displacement between its first and last sighting within `window`/2 either side over the
// time between them. The displacement is the sum of the registered shifts from each sighting
// to the next: between neighbouring scans the sensor moves 0.68 m at 6.8 m/s and sees the
// same faces, where over 1 s it moves 6.8 m and a long object's two ends (the only faces that
// fix its motion along its side) show in different scans (truck 100 registered 13 -> 23 in one
// go read 0.73 m/s with one ICP and under 0.5 with another; 13 -> 18 -> 23 added up to 0.45).
// Ten links of about 1 cm error each add up to about 3 cm, 0.03 m/s over 1 s.
// NaN where that cannot be measured (one sighting in the window, a link with too few points
// or a poor fit); the caller falls back to the box centres there.
// `points[i][k]` are box k of scan i's world-frame points (points_in_boxes).
std::vector<std::vector<double>> object_speeds(const std::vector<std::vector<LabelBox>>& boxes,
                                               const std::vector<std::vector<Eigen::Matrix3Xf>>& points,
                                               const std::vector<Eigen::Isometry3d>& poses,
                                               const std::vector<double>& times, double window,
                                               const ObjectMotionConfig& config = {});


// Box ground truth for a whole sequence, as `eval dynamic` and bench/dynamicmap_layout build
// it: which box moves in which scan.
enum class BoxSpeedSource {
  kPoints,   // the object's own points, registered (centres where that cannot be measured)
  kCentres,  // the box centres' line fit (`window`; 0: neighbouring scans), as before
};

struct BoxTruthOptions {
  double speed = 0.5;   // m/s: faster is moving
  double window = 1.0;  // s
  double margin = 0.1;  // m: boxes grown by this on every side
  // Centres stay the default truth for now: the issues' Pandar64 bars were set on it, and
  // which truth they are judged on is the project's call, with both in bench/quality.sh.
  BoxSpeedSource source = BoxSpeedSource::kCentres;
  // Raw sweeps without per-point time, placed in the world by their azimuth times (as the
  // layout and a preset with time_from_azimuth do): an object 5 m away moves across a quarter
  // of the sweep in 1 s of driving, so its rigidly placed points shift by up to 0.3 m.
  // A mover's whole track: an object that moves in any scan is moving in every scan it is in
  // (a truck that brakes to a stop beside the sensor, then stands), as a clean map of the log
  // wants it gone and as `run` decides (its tracker and the log's free space); per scan (the
  // default) it is moving only while it moves, as SemanticKITTI's moving classes are.
  bool whole_track = false;
  bool time_from_azimuth = false;
  double pose_reference = 0.5;  // where in its sweep a pose sits: 0 start, 0.5 middle, 1 end
};

struct BoxTruth {
  std::vector<std::vector<LabelBox>> boxes;
  std::vector<std::vector<bool>> moving;
  std::size_t measured = 0;  // boxes whose speed came from their points
  std::size_t stale_copies = 0;  // boxes left out of the motion estimate (stale_copies)
};

// Reads `boxes_dir` for every scan of `sequence` (which needs poses) and, with kPoints, every
// scan once more (read_raw_scan) for the points in its boxes.
BoxTruth box_truth(const Sequence& sequence, const std::filesystem::path& boxes_dir,
                   const BoxTruthOptions& options);

}  // namespace cleanmap
