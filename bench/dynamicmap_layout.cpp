// Turns a labelled sequence (SemanticKITTI labels/, or boxes/ with poses) into the DynamicMap
// benchmark's layout (Zhang et al., KTH): pcd/NNNNNN.pcd in the world frame with the sensor
// pose as VIEWPOINT, and gt_cloud.pcd, every point of every scan with intensity 1 when it
// moves and 0 when not. `cleanmap run --input OUT` then cleans it, and
// `cleanmap eval map --gt OUT/gt_cloud.pcd --output RUN/map_static.pcd` scores the result.
//
//   dynamicmap_layout --input SEQ --out DIR [--poses FILE] [--speed 0.5] [--speed-window 1] [--box-margin 0.1]
//                     [--box-speed points|centres]
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

#include "apps/box_truth_options.hpp"
#include "apps/cli_fields.hpp"
#include "pipeline/run_inputs.hpp"
#include "evaluation/box_labels.hpp"
#include "evaluation/object_motion.hpp"
#include "io/cloud_file.hpp"
#include "io/error.hpp"
#include "io/label_file.hpp"
#include "io/sequence.hpp"
#include "odometry/deskew.hpp"

namespace fs = std::filesystem;
using namespace cleanmap;

namespace {

struct Args {
  fs::path input, out, poses;
  BoxTruthOptions box;
};

// Per-point truth of scan i, 1 = moving.
class Truth {
 public:
  Truth(const Sequence& seq, const Args& a) : seq_(seq), margin_(a.box.margin) {
    if (seq.has_labels()) return;
    if (!fs::is_directory(a.input / "boxes")) {
      throw Error(a.input.string() + ": has neither labels/ (.label files) nor boxes/ (3D boxes)");
    }
    boxes_ = box_truth(seq, a.input / "boxes", a.box);
  }
  std::vector<std::uint8_t> of(std::size_t i, const Scan& raw) const {
    const auto labels = boxes_.boxes.empty() ? read_labels(seq_.labels[i], raw.size())
                                             : labels_from_boxes(raw, boxes_.boxes[i], boxes_.moving[i], margin_);
    std::vector<std::uint8_t> out(labels.size());
    for (std::size_t k = 0; k < labels.size(); ++k) out[k] = is_moving_label(labels[k]) ? 1 : 0;
    return out;
  }

 private:
  const Sequence& seq_;
  double margin_;
  BoxTruth boxes_;
};

void convert(const Args& a) {
  SequenceOptions so;
  so.poses_file = a.poses;
  const Sequence seq = open_sequence(a.input, so);
  if (seq.world_frame) throw Error(a.input.string() + ": already in the DynamicMap layout");
  if (!seq.has_poses()) throw Error(a.input.string() + ": no poses (give --poses, e.g. a run's poses.txt)");
  const Truth truth(seq, a);
  const PlatformMask mask = pipeline::platform_mask(seq, PlatformMaskConfig{});  // as `cleanmap run` learns it
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
    if (a.box.time_from_azimuth && !world.has_time()) {
      // The pose sits where the run that wrote it put it (deskew_reference).
      world.points = place_by_azimuth(world.points, seq.poses, seq.times, i, a.box.pose_reference);
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
  app::add_box_truth_options(app, a.box);
  CLI11_PARSE(app, argc, argv);
  try {
    convert(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynamicmap_layout: %s\n", e.what());
    return 1;
  }
  return 0;
}
