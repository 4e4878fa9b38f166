#include "io/depth_sequence.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "io/bag_common.hpp"
#include "io/close_checked.hpp"
#include "io/depth_image.hpp"
#include "io/error.hpp"
#include "io/pose_file.hpp"
#include "io/sequence.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

std::vector<Eigen::Isometry3d> frame_poses(const fs::path& file, PoseFormat format, const std::vector<double>& times) {
  const auto stamped = read_poses(file, format);
  if (stamped.empty()) fail(file, "holds no pose");
  std::vector<Eigen::Isometry3d> out;
  if (std::isnan(stamped.front().stamp)) {  // KITTI: one pose per frame
    if (stamped.size() != times.size()) {
      fail(file, "has " + std::to_string(stamped.size()) + " poses for " + std::to_string(times.size()) + " frames");
    }
    for (const auto& p : stamped) out.push_back(p.pose);
    return out;
  }
  std::map<double, Eigen::Isometry3d> track;
  for (const auto& p : stamped) track[p.stamp] = p.pose;
  check_coverage(file, track, times, "frame",
                 "trim depth.txt to the poses, or move the file away to estimate poses with odometry");
  for (double t : times) out.push_back(pose_at(track, t));
  return out;
}

}  // namespace

bool is_tum_rgbd(const fs::path& folder) {
  std::error_code ec;
  return fs::is_regular_file(folder / "depth.txt", ec) && fs::is_directory(folder / "depth", ec);
}

std::vector<DepthFrameEntry> read_depth_list(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  std::vector<DepthFrameEntry> out;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream s(line);
    DepthFrameEntry e{};
    if (!(s >> e.stamp >> e.file) || !std::isfinite(e.stamp)) fail(file, "line " + std::to_string(n) + ": expected 'stamp depth/NAME.png'");
    if (!out.empty() && !(e.stamp > out.back().stamp)) fail(file, "line " + std::to_string(n) + ": stamps must increase");
    out.push_back(e);
  }
  if (out.empty()) fail(file, "lists no depth frames");
  return out;
}

void write_depth_list(const fs::path& file, const std::vector<DepthFrameEntry>& frames) {
  std::ofstream out(file);
  out << "# depth maps\n# timestamp filename\n";
  out.precision(17);
  for (const auto& f : frames) out << std::fixed << f.stamp << " " << f.file << "\n";
  close_checked(out, file);
}

Sequence open_tum_rgbd(const fs::path& folder, const SequenceOptions& options) {
  Sequence seq;
  seq.root = folder;
  seq.layout = "tum-rgbd";
  seq.cloud = options.cloud;
  const auto frames = read_depth_list(folder / "depth.txt");
  for (const auto& f : frames) {
    seq.scans.push_back(folder / f.file);
    seq.times.push_back(f.stamp);
    const fs::path label = folder / "labels" / (fs::path(f.file).stem().string() + ".label");
    seq.labels.push_back(fs::exists(label) ? label : fs::path());
  }
  seq.times_source = (folder / "depth.txt").string();
  check_unique_names(seq);
  const fs::path poses = !options.poses_file.empty() ? options.poses_file : folder / "groundtruth.txt";
  if (fs::exists(poses) || !options.poses_file.empty()) {
    seq.poses = frame_poses(poses, options.pose_format, seq.times);
    seq.poses_source = poses.string() + " (interpolated at the frame stamps)";
  }
  const fs::path camera = options.camera_file.empty() ? folder / "camera.yaml" : options.camera_file;
  const auto intrinsics = std::make_shared<const DepthIntrinsics>(read_depth_intrinsics(camera));
  const Image16 first = read_png16(seq.scans.front());
  seq.image_width = first.width;
  seq.image_height = first.height;
  // A camera's principal point lies in its image, near the centre (issue 45: one thousands of
  // image widths away was accepted and every point landed far off to one side).
  const auto off_image = [](double c, int side) { return !(c >= -0.5 * side && c <= 1.5 * side); };
  if (off_image(intrinsics->cx, first.width) || off_image(intrinsics->cy, first.height)) {
    fail(camera, "principal point (cx " + std::to_string(intrinsics->cx) + ", cy " + std::to_string(intrinsics->cy) +
                     ") lies far outside the " + std::to_string(first.width) + " x " + std::to_string(first.height) +
                     " images of " + seq.scans.front().filename().string() + ": check the intrinsics' units (pixels)");
  }
  const auto files = std::make_shared<const std::vector<fs::path>>(seq.scans);
  seq.read_scan = [files, intrinsics, w = first.width, h = first.height](std::size_t index, TimeUnit) {
    const fs::path& file = files->at(index);
    const Image16 depth = read_png16(file);
    if (depth.width != w || depth.height != h) {
      fail(file, "is " + std::to_string(depth.width) + "x" + std::to_string(depth.height) + ", the first frame " +
                     std::to_string(w) + "x" + std::to_string(h));
    }
    Scan scan = depth_to_scan(depth, *intrinsics);
    scan.name = file.stem().string();
    return scan;
  };
  return seq;
}

}  // namespace cleanmap
