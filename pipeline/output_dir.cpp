#include "pipeline/output_dir.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <mutex>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap::pipeline {

void make_dirs(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail(dir, "cannot create output folder (" + ec.message() + ")");
}

void write_summary(const std::filesystem::path& out, nlohmann::json summary, bool complete,
                   const std::string& error) {
  summary["complete"] = complete;
  if (!error.empty()) summary["error"] = error;
  summary[kOutputMarker] = 1;  // this folder is a cleanmap output (output_claim.cpp)
  // One writer at a time: the interrupt watchdog (interrupt.cpp) may mark a summary while the
  // command writes its own.
  static std::mutex writing;
  const std::lock_guard<std::mutex> lock(writing);
  const auto tmp = out / "summary.json.tmp";
  {
    std::ofstream f(tmp);
    if (!f) fail(tmp, "cannot create file");
    // Replace, not throw, on invalid UTF-8: a message may quote a file's bytes.
    f << summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    close_checked(f, tmp);  // before the rename: a summary cut short never replaces the last one
  }
  std::filesystem::rename(tmp, out / "summary.json");
}

nlohmann::json json_number(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

nlohmann::json kitti_json(const KittiErrors& kitti) {
  nlohmann::json lengths = nlohmann::json::array();
  for (std::size_t k = 0; k < kitti.lengths.size(); ++k) {
    lengths.push_back({{"length", kitti.lengths[k]},
                       {"t_err_percent", json_number(kitti.t_err_by_length[k])},
                       {"r_err_deg_per_100m", json_number(kitti.r_err_by_length[k])}});
  }
  return {{"segments", kitti.segments.size()},
          {"t_err_percent", json_number(kitti.t_err_percent)},
          {"r_err_deg_per_100m", json_number(kitti.r_err_deg_per_100m)},
          {"by_length", lengths}};
}

void write_pose_files(const std::filesystem::path& out, const std::vector<StampedPose>& poses,
                      const std::optional<Eigen::Isometry3d>& kitti_tr) {
  std::vector<Eigen::Isometry3d> lidar, kitti;
  std::vector<StampedPose> kitti_stamped;
  for (const auto& p : poses) {
    lidar.push_back(p.pose);
    // KITTI ground truth is in the camera-0 frame: P_cam = Tr P_lidar Tr^-1.
    kitti.push_back(kitti_tr ? Eigen::Isometry3d(*kitti_tr * p.pose * kitti_tr->inverse()) : p.pose);
    kitti_stamped.push_back({p.stamp, kitti.back()});
  }
  // The two evaluation files share one frame (the ground truth's); poses.txt stays in the
  // lidar frame, so that OUT reads as a sequence.
  write_kitti_poses(out / "poses_kitti.txt", kitti);
  write_tum_poses(out / "poses_tum.txt", kitti_stamped);
  write_kitti_poses(out / "poses.txt", lidar);
  std::ofstream times(out / "times.txt");
  if (!times) fail(out / "times.txt", "cannot create file");
  times << std::fixed << std::setprecision(6);
  for (const auto& p : poses) times << p.stamp << '\n';
  close_checked(times, out / "times.txt");
}

nlohmann::json pose_files_json(const std::optional<Eigen::Isometry3d>& kitti_tr, double reference_offset) {
  const std::string eval_frame = kitti_tr ? "camera-0 (KITTI, Tr from calib.txt)" : "lidar";
  char when[160];
  std::snprintf(when, sizeof when, "each pose at its scan's stamp + %.4f s (the deskew reference)", reference_offset);
  return {{"poses_kitti.txt", eval_frame + ", one pose per scan, no stamps"},
          {"poses_tum.txt", eval_frame + ", stamped: " + when},
          {"poses.txt", "lidar, one pose per scan (with times.txt, OUT reads as a sequence)"},
          {"times.txt", "scan stamps + the deskew reference offset, s"}};
}

}  // namespace cleanmap::pipeline
