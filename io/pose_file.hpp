#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

namespace cleanmap {

// Pose at fraction s of the way from a (s = 0) to b (s = 1), constant linear and angular
// velocity; s outside [0, 1] extrapolates.
Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double s);

enum class PoseFormat { kAuto, kKitti, kTum };

// Parses "auto", "kitti", "tum"; throws Error on anything else.
PoseFormat parse_pose_format(const std::string& text);

struct StampedPose {
  double stamp = 0.0;  // seconds; NaN when the file carries no time (KITTI)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

// KITTI: 12 numbers per line (3x4 row-major). TUM: "t tx ty tz qx qy qz qw". Auto picks by the
// column count of the first line. Every line must have the same column count and finite values.
std::vector<StampedPose> read_poses(const std::filesystem::path& file,
                                    PoseFormat format = PoseFormat::kAuto);

void write_kitti_poses(const std::filesystem::path& file,
                       const std::vector<Eigen::Isometry3d>& poses);
void write_tum_poses(const std::filesystem::path& file, const std::vector<StampedPose>& poses);

// One time per line, in seconds.
std::vector<double> read_times(const std::filesystem::path& file);

// The `Tr:` line of a KITTI calib.txt (velodyne -> camera 0).
Eigen::Isometry3d read_kitti_calib_tr(const std::filesystem::path& file);

}  // namespace cleanmap
