#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/pose_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {

struct SequenceOptions {
  std::filesystem::path poses_file;  // instead of <folder>/poses.txt
  PoseFormat pose_format = PoseFormat::kAuto;
  std::filesystem::path times_file;  // instead of <folder>/times.txt
  double rate_hz = 10.0;             // scan spacing when no times are known
  // KITTI ground truth is in the camera-0 frame; with a calib.txt beside it, poses are turned
  // into lidar poses (Tr^-1 P Tr) unless this is false.
  bool kitti_poses_in_camera_frame = true;
  CloudReadOptions cloud;
  // ROS 1 bags (when built with bag support: a .bag file) and ROS 2 bags (a bag folder).
  std::string bag_topic;        // PointCloud2 topic; empty = the only one
  std::string bag_pose_topic;   // optional poses (Odometry, TransformStamped or tf)
  std::string bag_child_frame;  // with tf: the sensor frame
  // Depth-image sequences (TUM RGB-D layout): the camera's intrinsics; default <folder>/camera.yaml.
  std::filesystem::path camera_file;
};

// A log given as one folder (or a ROS 1 .bag file), found automatically: a ROS 2 bag folder
// (metadata.yaml with sqlite3 or mcap storage), a depth-image sequence in the TUM RGB-D layout
// (depth/*.png, depth.txt, optional groundtruth.txt, camera.yaml), a KITTI sequence (velodyne/*.bin, labels/,
// poses.txt, times.txt, calib.txt), a DynamicMap benchmark sequence (pcd/*.pcd: points already
// in the world frame, the sensor pose in each file's VIEWPOINT), a folder with a scans/
// subfolder, or a plain folder of .bin/.pcd/.ply scans, sorted by name. Scans are read one at a
// time (load_scan).
struct Sequence {
  std::filesystem::path root;
  std::string layout;  // "kitti", "dynamicmap", "scans-folder", "plain-folder", "rosbag", "ros2bag", "tum-rgbd"
  std::vector<std::filesystem::path> scans;
  std::vector<std::filesystem::path> labels;  // per scan; empty path where none
  std::vector<double> times;                  // per scan, seconds
  std::string times_source;                   // file name, "pose stamps" or "rate"
  std::vector<Eigen::Isometry3d> poses;       // sensor -> world per scan, or empty
  std::string poses_source;
  std::optional<Eigen::Isometry3d> calib_tr;  // KITTI velodyne -> camera 0
  bool world_frame = false;  // scans are already registered (DynamicMap); pose = VIEWPOINT
  // The local frame's origin in the poses' frame (world = local + origin): `poses` and
  // world-frame scans, as load_scan reads them, are relative to it (set_local_origin).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  CloudReadOptions cloud;
  // Layouts whose scans are not point files ("rosbag", "ros2bag": messages; "tum-rgbd": depth
  // images), read by index.
  std::function<Scan(std::size_t index, TimeUnit unit)> read_scan;
  int image_width = 0, image_height = 0;  // depth images: labels are written back as masks too

  std::size_t size() const { return scans.size(); }
  bool has_poses() const { return !poses.empty(); }
  bool has_labels() const;
};

Sequence open_sequence(const std::filesystem::path& folder, const SequenceOptions& options = {});

// Each scan's outputs are named after its file (labels/NAME.label, scores/NAME.bin): two scan
// files with one name (a.pcd and a.ply, or depth/1/x.png and depth/2/x.png) would overwrite each
// other's (issue 45). Throws Error naming both and the folder.
void check_unique_names(const Sequence& sequence);

// Georeferenced poses (UTM: hundreds to thousands of km) leave float points a grid of up to
// 0.5 m and OctoMap's 16-bit keys no room (they reach 9.8 km from the map's origin at 0.3 m):
// a run works relative to a local origin near its log. This one is the log's first position
// (its first pose, else its first world-frame point) rounded to the kilometre, so that a log
// within 500 m of its frame's origin keeps that origin, and logs of one area mostly share one.
Eigen::Vector3d local_origin_near(const Eigen::Vector3d& first_position);
Eigen::Vector3d automatic_local_origin(const Sequence& sequence);

// Re-expresses the sequence's poses, and its world-frame scans as load_scan reads them,
// relative to `origin` (in the poses' frame). Call once, before any scan is loaded.
void set_local_origin(Sequence& sequence, const Eigen::Vector3d& origin);

struct LoadedScan {
  Scan scan;                          // NaN/inf points dropped, stamp and pose set
  std::vector<std::uint32_t> labels;  // per kept point when the sequence has labels
  std::size_t dropped_non_finite = 0;
  std::size_t dropped_out_of_range = 0;  // beyond kMaxCoordinate / kMaxPointTime (io/scan.hpp)
  // A world-frame scan without a VIEWPOINT (or the identity, PCD's default): placed at the
  // frame's origin.
  bool viewpoint_missing = false;
};

LoadedScan load_scan(const Sequence& sequence, std::size_t index);

// Scan `index` as its input holds it (sensor frame, every point, nothing dropped), whatever the
// layout: a file, a bag message or a depth image.
Scan read_raw_scan(const Sequence& sequence, std::size_t index);

// Reads a single scan file of any supported format (.bin, .pcd, .ply).
Scan read_scan_file(const std::filesystem::path& file, const CloudReadOptions& options = {});

}  // namespace cleanmap
