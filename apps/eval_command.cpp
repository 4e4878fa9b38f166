#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "apps/box_truth_options.hpp"
#include "apps/commands.hpp"
#include "apps/cli_fields.hpp"
#include "apps/map_truth.hpp"
#include "pipeline/output_dir.hpp"
#include "apps/preset_options.hpp"
#include "evaluation/box_labels.hpp"
#include "evaluation/dynamic_metrics.hpp"
#include "evaluation/map_metrics.hpp"
#include "evaluation/object_motion.hpp"
#include "evaluation/trajectory_metrics.hpp"
#include "io/close_checked.hpp"
#include "io/cloud_file.hpp"
#include "io/label_file.hpp"
#include "io/sequence.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

nlohmann::json stats_json(const ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}, {"count", s.count}};
}

void write_json(const fs::path& file, const nlohmann::json& j) {
  if (file.empty()) return;
  std::ofstream out(file);
  if (!out) fail(file, "cannot create file");
  out << j.dump(2) << '\n';
  close_checked(out, file);
}

struct TrajectoryArgs {
  fs::path est, ref, json;
  std::string format = "auto", align = "se3";
  int delta = 1;
  double max_dt = 0.02;
};

void eval_trajectory(const TrajectoryArgs& a) {
  const auto fmt = parse_pose_format(a.format);
  const auto ref = read_poses(a.ref, fmt);
  const auto est = read_poses(a.est, fmt);
  std::vector<Eigen::Isometry3d> r, e;
  if (ref.size() < 2) fail(a.ref, "nothing to measure: " + std::to_string(ref.size()) + " pose(s), errors need two or more");
  if (est.size() < 2) fail(a.est, "nothing to measure: " + std::to_string(est.size()) + " pose(s), errors need two or more");
  const bool stamped = !std::isnan(ref.front().stamp) && !std::isnan(est.front().stamp);
  if (stamped) {
    // The reference is interpolated between neighbours up to 2.5 of its own median spacing
    // apart (a dropped sample, not a hole in the log).
    std::vector<double> gaps;
    for (std::size_t k = 1; k < ref.size(); ++k) gaps.push_back(ref[k].stamp - ref[k - 1].stamp);
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    interpolate_reference(ref, est, 2.5 * gaps[gaps.size() / 2], a.max_dt, r, e);
    if (r.size() < 2) {
      fail(a.est, "fewer than two poses lie within the reference's time span (stamps " + format_number(est.front().stamp) +
                      "... against " + format_number(ref.front().stamp) + "..." + format_number(ref.back().stamp) + ")");
    }
  } else {
    if (ref.size() != est.size()) {
      fail(a.est, "has " + std::to_string(est.size()) + " poses, the reference " +
                      std::to_string(ref.size()) + " (KITTI files pair by line)");
    }
    for (const auto& p : ref) r.push_back(p.pose);
    for (const auto& p : est) e.push_back(p.pose);
  }
  if (static_cast<std::size_t>(a.delta) >= r.size()) {
    fail(a.est, "nothing to measure: --delta " + std::to_string(a.delta) + " frames is not shorter than the " +
                    std::to_string(r.size()) + " paired poses");
  }
  const Alignment alignment = a.align == "none" ? Alignment::kNone : a.align == "sim3" ? Alignment::kSim3 : Alignment::kSE3;
  const double heading = heading_difference_deg(r, e);
  if (heading > 45.0) {
    std::fprintf(stderr, "cleanmap: warning: the two trajectories head %.0f deg apart in their first frames: are the "
                 "files in different frames? (KITTI ground truth is in the camera-0 frame: compare poses_kitti.txt "
                 "or poses_tum.txt, not poses.txt)\n", heading);
  }
  const auto kitti = kitti_errors(r, e);
  const auto ape = absolute_pose_error(r, e, alignment);
  const auto rpe = relative_pose_error(r, e, a.delta);
  std::printf("poses paired: %zu%s\n", r.size(), stamped ? " (by time stamp, reference interpolated)" : " (by line)");
  std::printf("KITTI segment errors (devkit): %zu segments\n", kitti.segments.size());
  std::printf("  length [m]  t_err [%%]  r_err [deg/100m]\n");
  for (std::size_t k = 0; k < kitti.lengths.size(); ++k) {
    std::printf("  %10.0f  %9.3f  %16.4f\n", kitti.lengths[k], kitti.t_err_by_length[k], kitti.r_err_by_length[k]);
  }
  std::printf("  overall     %9.3f  %16.4f\n", kitti.t_err_percent, kitti.r_err_deg_per_100m);
  std::printf("APE (%s aligned) translation [m]: rmse %.4f mean %.4f median %.4f max %.4f\n",
              a.align.c_str(), ape.translation.rmse, ape.translation.mean, ape.translation.median, ape.translation.max);
  std::printf("RPE (delta %d frames): translation rmse %.4f m, rotation rmse %.4f deg\n", a.delta,
              rpe.translation.rmse, rpe.rotation.rmse);
  write_json(a.json, {{"paired", r.size()},
                      {"kitti", kitti_json(kitti)},
                      {"ape", {{"alignment", a.align}, {"scale", ape.scale}, {"translation", stats_json(ape.translation)}}},
                      {"rpe", {{"delta_frames", a.delta}, {"translation", stats_json(rpe.translation)},
                               {"rotation_deg", stats_json(rpe.rotation)}}}});
}

struct DynamicArgs {
  fs::path pred, gt, json, poses;
  double max_range = 0.0;
  BoxTruthOptions box;
};

void eval_dynamic(const DynamicArgs& a) {
  SequenceOptions so;
  so.poses_file = a.poses;
  const Sequence seq = open_sequence(a.gt, so);
  const bool from_boxes = !seq.has_labels() && fs::is_directory(a.gt / "boxes");
  if (!seq.has_labels() && !from_boxes) {
    fail(a.gt, "has neither labels/ (.label files) nor boxes/ (3D boxes) for ground truth");
  }
  BoxTruth boxes;
  if (from_boxes) {
    if (!seq.has_poses()) fail(a.gt, "boxes need poses to tell moving objects: give --poses (e.g. a run's poses.txt)");
    boxes = box_truth(seq, a.gt / "boxes", a.box);
    std::size_t n_moving = 0, n_boxes = 0;
    for (const auto& m : boxes.moving) {
      n_boxes += m.size();
      for (bool b : m) n_moving += b;
    }
    std::printf("ground truth from boxes: %zu of %zu boxes moving faster than %.2f m/s (%zu speeds measured on the "
                "objects' points; %zu stale copies of older boxes judged by their objects' nearest sightings)\n",
                n_moving, n_boxes, a.box.speed, boxes.measured, boxes.stale_copies);
  }
  const fs::path dir = fs::is_directory(a.pred / "labels") ? a.pred / "labels" : a.pred;
  MovingConfusion total;
  nlohmann::json scans = nlohmann::json::array();
  for (std::size_t i = 0; i < seq.size(); ++i) {
    if (!from_boxes && seq.labels[i].empty()) continue;
    const Scan scan = read_raw_scan(seq, i);
    const auto truth = from_boxes ? labels_from_boxes(scan, boxes.boxes[i], boxes.moving[i], a.box.margin)
                                  : read_labels(seq.labels[i], scan.size());
    const auto pred_file = dir / (seq.scans[i].stem().string() + ".label");
    if (!fs::exists(pred_file)) fail(pred_file, "missing: no prediction for a labelled scan");
    const auto pred = read_labels(pred_file, scan.size());
    MovingConfusion c;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const auto p = scan.points.col(static_cast<Eigen::Index>(k));
      if (!p.allFinite()) continue;
      if (a.max_range > 0 && p.norm() > a.max_range) continue;  // sensor frame: range from origin
      count(c, semantic_class(pred[k]) == kLabelMoving, is_moving_label(truth[k]),
            semantic_class(pred[k]) != kLabelUnscored);
    }
    total += c;
    std::printf("  %s  IoU %.3f  precision %.3f  recall %.3f\n", seq.scans[i].stem().c_str(), c.iou(),
                c.precision(), c.recall());
    scans.push_back({{"scan", seq.scans[i].stem().string()}, {"iou", json_number(c.iou())},
                     {"precision", json_number(c.precision())}, {"recall", json_number(c.recall())}});
  }
  std::printf("moving class: IoU %.3f  precision %.3f  recall %.3f  (tp %zu fp %zu fn %zu)\n",
              total.iou(), total.precision(), total.recall(), total.tp, total.fp, total.fn);
  write_json(a.json, {{"iou", json_number(total.iou())}, {"precision", json_number(total.precision())},
                      {"recall", json_number(total.recall())}, {"max_range", a.max_range}, {"scans", scans}});
}

struct MapArgs {
  fs::path gt, output, json;
  double distance = 0.05;
};

void eval_map(const MapArgs& a) {
  const auto [gt, dynamic] = read_map_truth(a.gt);
  const Scan out = read_cloud(a.output);
  if (gt.size() == 0) fail(a.gt, "has no points: nothing to measure");
  const auto s = score_map(gt.points, dynamic, out.points, a.distance);
  std::printf("DynamicMap benchmark: SA %.3f  DA %.3f  AA %.3f  HA %.3f  (%zu static, %zu dynamic ground-truth points)\n"
              "DA at most %.3f while every static point is kept (the static truth itself as the output)\n",
              s.sa, s.da, s.aa, s.ha, s.static_points, s.dynamic_points, s.da_ceiling);
  write_json(a.json, {{"SA", json_number(s.sa)}, {"DA", json_number(s.da)}, {"AA", json_number(s.aa)}, {"HA", json_number(s.ha)},
                      {"DA_ceiling", json_number(s.da_ceiling)}, {"static_points", s.static_points}, {"dynamic_points", s.dynamic_points},
                      {"static_kept", s.static_kept}, {"dynamic_removed", s.dynamic_removed}});
}

}  // namespace

void register_eval(CLI::App& app) {
  auto* eval = app.add_subcommand("eval", "Trajectory, dynamic-point and map-quality metrics");
  eval->require_subcommand(1);

  auto t = std::make_shared<TrajectoryArgs>();
  auto* tc = eval->add_subcommand("trajectory", "KITTI segment errors (devkit), APE and RPE");
  tc->add_option("--est", t->est, "Estimated poses (KITTI or TUM)")->required();
  tc->add_option("--ref", t->ref, "Reference poses (KITTI or TUM)")->required();
  tc->add_option("--format", t->format, "auto, kitti or tum")->capture_default_str();
  tc->add_option("--align", t->align, "APE alignment")->check(CLI::IsMember({"none", "se3", "sim3"}))->capture_default_str();
  tc->add_option("--delta", t->delta, "RPE step in frames")->check(number_in(kAtLeastOne))->capture_default_str();
  tc->add_option("--max-dt", t->max_dt, "TUM: how far beyond the reference's ends an estimate may lie, s")->check(number_in(kPositive))->capture_default_str();
  tc->add_option("--json", t->json, "Also write the numbers to this JSON file");
  tc->callback([t] { eval_trajectory(*t); });

  auto d = std::make_shared<DynamicArgs>();
  auto* dc = eval->add_subcommand("dynamic", "Moving-class IoU, precision, recall of predicted labels");
  dc->add_option("--pred", d->pred, "Folder of predicted .label files (or a run/score output)")->required();
  dc->add_option("--gt", d->gt, "Sequence folder with labels/ (or boxes/ and --poses)")->required();
  dc->add_option("--poses", d->poses, "Poses for box ground truth (e.g. a run's poses.txt)");
  add_box_truth_options(*dc, d->box);
  dc->add_option("--max-range", d->max_range, "Only points within this range, m (0 = all)")
      ->check(number_in(kNonNegative))->capture_default_str();
  dc->add_option("--json", d->json, "Also write the numbers to this JSON file");
  dc->callback([d] { eval_dynamic(*d); });

  auto m = std::make_shared<MapArgs>();
  auto* mc = eval->add_subcommand("map", "DynamicMap benchmark scores (SA, DA, AA, HA) of a cleaned cloud");
  mc->add_option("--gt", m->gt, "gt_cloud.pcd (intensity 0 static, 1 dynamic)")->required();
  mc->add_option("--output", m->output, "The method's cloud of kept points")->required();
  mc->add_option("--distance", m->distance, "Kept when an output point is this close, m")
      ->check(number_in(kPositive))->capture_default_str();
  mc->add_option("--json", m->json, "Also write the numbers to this JSON file");
  mc->callback([m] { eval_map(*m); });
}

}  // namespace cleanmap::app
