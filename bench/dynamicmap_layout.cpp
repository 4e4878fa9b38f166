// Turns a labelled sequence (SemanticKITTI labels/, or boxes/ with poses) into the DynamicMap
// benchmark's layout (Zhang et al., KTH): pcd/NNNNNN.pcd in the world frame with the sensor
// pose as VIEWPOINT, and gt_cloud.pcd, every point of every scan with intensity 1 when it
// moves and 0 when not. `cleanmap run --input OUT` then cleans it, and
// `cleanmap eval map --gt OUT/gt_cloud.pcd --output RUN/map_static.pcd` scores the result.
//
//   dynamicmap_layout --input SEQ --out DIR [--poses FILE] [--speed 0.5] [--speed-window 1] [--box-margin 0.1]
//                     [--time-from-azimuth [--pose-reference middle]]
//
// With --time-from-azimuth (scans without per-point time, as a preset with time_from_azimuth
// runs them), every point is placed with the pose at its own time (times from azimuth,
// relative to where the poses sit in the sweep: the middle for `cleanmap run`'s poses unless
// its deskew_reference says otherwise, --pose-reference; constant velocity
// between neighbouring poses): the poses of a deskewing run fit deskewed scans, and raw ones
// put on them smear by up to half the sweep's travel (0.3 m at 6 m/s).
//
// The recording platform (points fixed in the sensor frame, learnt as `cleanmap run` does) is
// left out, as the benchmark's own sequences have the ego vehicle removed. Non-finite points
// are left out too.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/config_fields.hpp"
#include "apps/run_inputs.hpp"
#include "evaluation/box_labels.hpp"
#include "io/cloud_file.hpp"
#include "io/error.hpp"
#include "io/label_file.hpp"
#include "io/sequence.hpp"
#include "odometry/deskew.hpp"
#include "odometry/preprocess.hpp"

namespace fs = std::filesystem;
using namespace cleanmap;

namespace {

struct Args {
  fs::path input, out, poses;
  double speed = 0.5;
  double speed_window = 1.0;
  double box_margin = 0.1;
  bool time_from_azimuth = false;
  double pose_reference = 0.5;  // where in its sweep a scan's pose sits: 0 start, 0.5 middle, 1 end
};

// Per-point truth of scan i, 1 = moving.
class Truth {
 public:
  Truth(const Sequence& seq, const Args& a) : seq_(seq), margin_(a.box_margin) {
    if (seq.has_labels()) return;
    if (!fs::is_directory(a.input / "boxes")) {
      throw Error(a.input.string() + ": has neither labels/ (.label files) nor boxes/ (3D boxes)");
    }
    boxes_ = read_sequence_boxes(a.input / "boxes", seq.scans);
    moving_ = moving_boxes(boxes_, seq.poses, seq.times, a.speed, a.speed_window);
  }
  std::vector<std::uint8_t> of(std::size_t i, const Scan& raw) const {
    const auto labels = boxes_.empty() ? read_labels(seq_.labels[i], raw.size())
                                       : labels_from_boxes(raw, boxes_[i], moving_[i], margin_);
    std::vector<std::uint8_t> out(labels.size());
    for (std::size_t k = 0; k < labels.size(); ++k) out[k] = is_moving_label(labels[k]) ? 1 : 0;
    return out;
  }

 private:
  const Sequence& seq_;
  double margin_;
  std::vector<std::vector<LabelBox>> boxes_;
  std::vector<std::vector<bool>> moving_;
};

void convert(const Args& a) {
  SequenceOptions so;
  so.poses_file = a.poses;
  const Sequence seq = open_sequence(a.input, so);
  if (seq.world_frame) throw Error(a.input.string() + ": already in the DynamicMap layout");
  if (!seq.has_poses()) throw Error(a.input.string() + ": no poses (give --poses, e.g. a run's poses.txt)");
  const Truth truth(seq, a);
  const PlatformMask mask = app::platform_mask(seq, PlatformMaskConfig{});  // as `cleanmap run` learns it
  fs::create_directories(a.out / "pcd");
  std::vector<Eigen::Vector3f> gt_points;
  std::vector<float> gt_moving;
  std::size_t masked = 0, moving = 0;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const Scan raw = read_raw_scan(seq, i);
    const auto is_moving = truth.of(i, raw);
    std::vector<std::int32_t> keep;
    for (Eigen::Index k = 0; k < raw.points.cols(); ++k) {
      const Eigen::Vector3f p = raw.points.col(k);
      if (!p.allFinite()) continue;
      if (!mask.empty() && mask.contains(p)) {
        ++masked;
        continue;
      }
      keep.push_back(static_cast<std::int32_t>(k));
    }
    Scan world = select_points(raw, keep);
    if (a.time_from_azimuth && !world.has_time() && !world.empty()) {
      const double sweep = i + 1 < seq.size() ? seq.times[i + 1] - seq.times[i] : i > 0 ? seq.times[i] - seq.times[i - 1] : 0.1;
      // The pose sits where the run that wrote it put it (deskew_reference), a share of the
      // sweep's last point time, as the run measures it.
      world.time = times_from_azimuth(world.points, sweep);
      world.time.array() -= static_cast<float>(a.pose_reference) * world.time.maxCoeff();
      world.points = to_world(world, sweep_motion(seq.poses, seq.times, i)).points;
    } else {
      world.points = (seq.poses[i].cast<float>() * world.points).eval();
    }
    world.time.resize(0);  // the benchmark's files carry x y z intensity
    CloudWriteOptions o;
    o.viewpoint = seq.poses[i];
    char name[32];
    std::snprintf(name, sizeof name, "%06zu.pcd", i);
    write_cloud(a.out / "pcd" / name, world, {}, o);
    for (std::size_t j = 0; j < keep.size(); ++j) {
      gt_points.push_back(world.points.col(static_cast<Eigen::Index>(j)));
      gt_moving.push_back(is_moving[static_cast<std::size_t>(keep[j])]);
      moving += is_moving[static_cast<std::size_t>(keep[j])];
    }
  }
  Scan gt;
  gt.points.resize(3, static_cast<Eigen::Index>(gt_points.size()));
  for (std::size_t k = 0; k < gt_points.size(); ++k) gt.points.col(static_cast<Eigen::Index>(k)) = gt_points[k];
  gt.intensity = Eigen::Map<Eigen::VectorXf>(gt_moving.data(), static_cast<Eigen::Index>(gt_moving.size()));
  write_cloud(a.out / "gt_cloud.pcd", gt);
  std::printf("%s: %zu scans, %zu points (%zu moving), %zu platform points left out\n", a.out.c_str(),
              seq.size(), gt_points.size(), moving, masked);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"A labelled sequence in the DynamicMap benchmark layout (pcd/ + gt_cloud.pcd)"};
  Args a;
  app.add_option("--input", a.input, "Sequence with labels/ or boxes/")->required();
  app.add_option("--out", a.out, "Output folder")->required();
  app.add_option("--poses", a.poses, "Pose file (default: the sequence's poses.txt)");
  app.add_option("--speed", a.speed, "Boxes faster than this (m/s, world frame) are moving")
      ->check(app::number_in(app::kNonNegative))->capture_default_str();
  app.add_option("--speed-window", a.speed_window, "Box speed from a line fitted over this many seconds (0: neighbouring scans)")
      ->check(app::number_in(app::kNonNegative))->capture_default_str();
  app.add_option("--box-margin", a.box_margin, "Boxes grown by this on every side, m")
      ->check(app::number_in(app::kNonNegative))->capture_default_str();
  app.add_flag("--time-from-azimuth", a.time_from_azimuth, "Place points at their time (from azimuth) along the poses");
  const std::map<std::string, double> reference{{"start", 0.0}, {"middle", 0.5}, {"end", 1.0}};
  app.add_option("--pose-reference", a.pose_reference,
                 "Where in its sweep each pose sits, as the run that wrote the poses (deskew_reference): start, middle, end")
      ->transform(CLI::CheckedTransformer(reference))
      ->default_str("middle");
  CLI11_PARSE(app, argc, argv);
  try {
    convert(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynamicmap_layout: %s\n", e.what());
    return 1;
  }
  return 0;
}
