#pragma once

// The config tables of every command: one Field per setting (YAML key and --option), grouped
// in the preset sections "input" and "scorer".

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>

#include "pipeline/config_fields.hpp"
#include "dynamics/scorer_config.hpp"
#include "io/sequence.hpp"
#include "mapping/free_space_vote.hpp"
#include "mapping/octomap_builder.hpp"
#include "mapping/visibility_map.hpp"
#include "odometry/odometry_config.hpp"
#include "odometry/platform_mask.hpp"

namespace cleanmap::pipeline {

struct InputSettings {
  std::string poses;              // pose file (KITTI or TUM); default <input>/poses.txt
  std::string pose_format = "auto";
  std::string times;              // scan times, one per line; default <input>/times.txt
  double rate_hz = 10.0;          // scan spacing when no times are known
  std::string time_unit = "auto"; // of per-point time fields in PCD/PLY
  bool kitti_camera_poses = true; // KITTI poses + calib.txt: convert camera -> lidar frame
  double eval_max_range = 0.0;    // metres from the sensor for label metrics; 0 = all
  std::string bag_topic;          // ROS bag input: PointCloud2 topic (empty = the only one)
  std::string bag_pose_topic;     // ROS bag input: Odometry / TransformStamped / tf topic
  std::string bag_child_frame;    // ROS bag input with tf: the sensor frame
  std::string camera;             // depth-image input: intrinsics file; default <input>/camera.yaml
  PlatformMaskConfig platform;    // the recording platform's own returns, masked
  // The map's local origin in the poses' frame, x y z (empty: the log's first position rounded
  // to the kilometre, io/sequence.hpp). Runs to be merged into one map give the same one.
  std::vector<double> map_origin;
};

inline auto input_fields() {
  return std::make_tuple(
      CLEANMAP_FIELD("poses", poses, "Pose file (KITTI 3x4 or TUM); default <input>/poses.txt"),
      CLEANMAP_FIELD("pose_format", pose_format, "auto, kitti or tum"),
      CLEANMAP_FIELD("times", times, "Scan times file; default <input>/times.txt"),
      CLEANMAP_FIELD_IN("rate_hz", rate_hz, kPositive, "Scan rate when no times are given"),
      CLEANMAP_FIELD("time_unit", time_unit, "Unit of per-point time fields: auto, s, ms, us, ns"),
      CLEANMAP_FIELD("kitti_camera_poses", kitti_camera_poses,
                     "KITTI poses are camera-0 poses (converted with Tr from calib.txt)"),
      CLEANMAP_FIELD_IN("eval_max_range", eval_max_range, kNonNegative,
                     "Only points within this range (m) count in label metrics; 0 = all"),
      CLEANMAP_FIELD("bag_topic", bag_topic, "ROS 1 or 2 bag: PointCloud2 topic (default: the only one)"),
      CLEANMAP_FIELD("bag_pose_topic", bag_pose_topic, "ROS 1 or 2 bag: Odometry, TransformStamped or tf topic"),
      CLEANMAP_FIELD("bag_child_frame", bag_child_frame, "ROS 1 or 2 bag with tf: the sensor's frame id"),
      CLEANMAP_FIELD("camera", camera, "Depth images: intrinsics YAML (fx fy cx cy depth_scale ...); default <input>/camera.yaml"),
      CLEANMAP_FIELD("self_mask", platform.automatic, "Mask the recording platform (returns fixed in the sensor frame)"),
      CLEANMAP_FIELD_IN("self_mask_scans", platform.learn_scans, kAtLeastOne, "Scans the platform mask is learnt from"),
      CLEANMAP_FIELD_IN("self_mask_range", platform.max_range, kPositive, "Only points this close can be the platform, m"),
      CLEANMAP_FIELD_IN("self_mask_voxel", platform.voxel, kPositive, "Sensor-frame cell of the platform mask, m"),
      CLEANMAP_FIELD_IN("self_mask_share", platform.min_share, kShare, "Share of scans a platform cell is occupied in"),
      CLEANMAP_FIELD("crop_box", platform.crop_box, "Sensor-frame box always masked: xmin ymin zmin xmax ymax zmax, m"),
      CLEANMAP_FIELD("map_origin", map_origin,
                     "Map's local origin in the poses' frame, x y z m (default: first position rounded to 1 km)"));
}

inline SequenceOptions sequence_options(const InputSettings& s) {
  SequenceOptions o;
  o.poses_file = s.poses;
  o.pose_format = parse_pose_format(s.pose_format);
  o.times_file = s.times;
  o.rate_hz = s.rate_hz;
  o.kitti_poses_in_camera_frame = s.kitti_camera_poses;
  o.cloud.time_unit = parse_time_unit(s.time_unit);
  o.bag_topic = s.bag_topic;
  o.bag_pose_topic = s.bag_pose_topic;
  o.bag_child_frame = s.bag_child_frame;
  o.camera_file = s.camera;
  return o;
}

inline auto scorer_fields() {
  return std::make_tuple(
      CLEANMAP_FIELD_IN("voxel_size", voxel_size, kNonNegative, "d_v in m; 0 = bounding-box diagonal / voxel_divisor"),
      CLEANMAP_FIELD_IN("voxel_divisor", voxel_divisor, kPositive, "Relative voxel size divisor (paper: 600)"),
      CLEANMAP_FIELD_IN("window_half", window_half, (Range{1, 1000}), "N: the window holds 2N+1 scans"),
      CLEANMAP_FIELD_IN("radius", radius, (Range{0.001, 100}), "d_r: neighbourhood radius, m"),
      CLEANMAP_FIELD_IN("threshold", threshold, kShare, "thr on the score |n_t|"),
      CLEANMAP_FIELD_IN("time_scale", time_scale, kNonNegative, "Metres one second weighs in the 4D PCA"),
      CLEANMAP_FIELD_IN("pose_noise", pose_noise, kNonNegative, "Pose error per scan (1 sigma), m: motion it can fake is not dynamic"),
      CLEANMAP_FIELD_IN("pose_noise_deg", pose_noise_deg, kNonNegative, "Pose rotation error per scan (1 sigma), degrees"),
      CLEANMAP_FIELD_IN("min_neighbors", min_neighbors, kAtLeastOne, "Fewer neighbours: not scored"),
      CLEANMAP_FIELD_IN("max_eigen_ratio", max_eigen_ratio, kNonNegative, "Not scored when l0 > ratio * l1 (no clear normal); 0 = off"),
      CLEANMAP_FIELD("mode", mode, "fast (per-cell sums) or exact (kd-tree)"),
      CLEANMAP_FIELD_IN("cell_size", cell_size, kNonNegative, "Fast mode's statistics grid, m; 0 = radius"),
      CLEANMAP_FIELD("upsample", upsample, "nearest or paper"),
      CLEANMAP_FIELD_IN("upsample_radius", upsample_radius, (Range{0.001, 100}), "Upsampling radius, m"),
      CLEANMAP_FIELD("ground_aware", ground_aware, "Score ground and non-ground points apart"),
      CLEANMAP_FIELD("ground_static", ground_static, "Ground points are never dynamic on their own"),
      CLEANMAP_FIELD_IN("ground_cell", ground.cell, kPositive, "Ground grid cell, m"),
      CLEANMAP_FIELD_IN("ground_height", ground.height, kNonNegative, "Height above the local ground that is ground, m"),
      CLEANMAP_FIELD_IN("ground_max_slope", ground.max_slope, kNonNegative, "Steepest ground, rise per metre"),
      CLEANMAP_FIELD_IN("ground_reach", ground.reach, kPositive, "Lowest points this far away bound a cell's ground, m"),
      CLEANMAP_FIELD_IN("ground_floor_band", ground.floor_band, kNonNegative, "Ground this close above the floor is the floor itself (keeps its own decision in paper upsampling), m"),
      CLEANMAP_FIELD("object_completion", object_completion, "Grow decisions to whole clusters"),
      CLEANMAP_FIELD_IN("cluster_radius", objects.radius, kPositive, "Euclidean clustering distance, m"),
      CLEANMAP_FIELD_IN("cluster_min_fraction", objects.min_fraction, kShare, "Share of a cluster's scored points that must be dynamic"),
      CLEANMAP_FIELD_IN("cluster_min_dynamic", objects.min_votes, (Range{1, 1e6}), "Dynamic points a cluster needs"),
      CLEANMAP_FIELD_IN("cluster_max_extent", objects.max_extent, kPositive, "Clusters wider than this (m) are split, not completed"),
      CLEANMAP_FIELD_IN("cluster_min_split_radius", objects.min_split_radius, kPositive, "Over-large clusters are re-clustered at half the radius down to this, m"),
      CLEANMAP_FIELD("track_objects", tracks.enabled, "Follow objects across the window: a mover stays dynamic where the normals miss it"),
      CLEANMAP_FIELD_IN("track_max_speed", tracks.max_speed, kPositive, "Motion allowed between two sightings of one object, m/s"));
}

inline auto odometry_fields() {
  return std::make_tuple(
      CLEANMAP_FIELD_IN("min_range", min_range, kNonNegative, "Drop closer returns, m"),
      CLEANMAP_FIELD_IN("max_range", max_range, kPositive, "Drop farther returns, m"),
      CLEANMAP_FIELD_IN("map_voxel_size", map_voxel_size, kPositive, "Local-map voxel, m"),
      CLEANMAP_FIELD_IN("max_points_per_voxel", max_points_per_voxel, kAtLeastOne, "Local-map points per voxel"),
      CLEANMAP_FIELD_IN("map_radius", map_radius, kPositive, "Local-map voxels beyond this distance are dropped, m"),
      CLEANMAP_FIELD_IN("registration_voxel", registration_voxel, kPositive, "Registration downsampling, x map_voxel_size"),
      CLEANMAP_FIELD_IN("initial_threshold", initial_threshold, kPositive, "Correspondence distance before motion is known, m"),
      CLEANMAP_FIELD_IN("min_motion", min_motion, kNonNegative, "Smaller steps do not update the adaptive threshold, m"),
      CLEANMAP_FIELD_IN("max_icp_iterations", max_icp_iterations, kAtLeastOne, "Correspondence searches per scan"),
      CLEANMAP_FIELD_IN("solver_iterations", solver_iterations, kAtLeastOne, "Ceres iterations per correspondence set"),
      CLEANMAP_FIELD_IN("convergence", convergence, kPositive, "Stop when the pose changes less (m, rad)"),
      CLEANMAP_FIELD_IN("normal_neighbors", normal_neighbors, (Range{3, 1000}), "Map points per local plane"),
      CLEANMAP_FIELD_IN("min_points", min_points, kNonNegative, "Fewer points: degenerate scan"),
      CLEANMAP_FIELD("deskew", deskew, "Undistort scans with per-point times"),
      CLEANMAP_FIELD("deskew_reference", deskew_reference, "Time a pose refers to: start, middle or end of the sweep"),
      CLEANMAP_FIELD("time_from_azimuth", time_from_azimuth, "Derive per-point times from azimuth when absent"),
      CLEANMAP_FIELD_IN("vertical_correction_deg", vertical_correction_deg, (Range{-10, 10}), "KITTI HDL-64 vertical angle fix (0.205)"),
      CLEANMAP_FIELD("exclude_dynamic", exclude_dynamic, "Remove scorer-labelled dynamic points from the local map"),
      CLEANMAP_FIELD("level_first_scan", level_first_scan, "Level the world frame on the first scan's dominant plane (depth cameras)"));
}

// Map and output settings of `cleanmap run` (preset section "mapping").
struct MappingSettings {
  MapConfig map;
  double cloud_voxel = 0.05;      // voxel filter of map_static.pcd (raw points kept), m; 0 = all
  // Ray casting is the cost of an OctoMap: every 2nd scan (5 Hz) carves nearly the same free
  // space in half the time (measured on the synthetic street, see README).
  int insert_every = 2;
  bool write_raw_map = false;     // also map_raw.pcd: the map without removal
  bool free_space = true;         // add the OctoMap free-space opinion to the scorer's
  ObjectRule free_space_objects = kFreeSpaceRule;  // when a cluster is dynamic by free space
  double free_space_voxel = 0.2;  // the votes' subsample: one vote per voxel (a street: 0.2 m)
  VisibilityConfig visibility;    // offline runs: the log-wide map of cells seen through
  bool occupancy_grid = false;    // 2D grid (PGM + YAML, ROS map_server)
  double grid_z_min = 0.3;        // heights above the local ground that count for the grid, m
  double grid_z_max = 2.0;
};

inline auto mapping_fields() {
  return std::make_tuple(
      CLEANMAP_FIELD_IN("resolution", map.resolution, (Range{0.001, 100}), "OctoMap leaf size, m"),
      CLEANMAP_FIELD_IN("map_max_range", map.max_range, kPositive, "Rays longer than this are cut, m"),
      CLEANMAP_FIELD_IN("prob_hit", map.prob_hit, (Range{0.5, 1, true}), "OctoMap hit probability"),
      CLEANMAP_FIELD_IN("prob_miss", map.prob_miss, (Range{0, 0.5, true}), "OctoMap miss probability"),
      CLEANMAP_FIELD_IN("clamp_min", map.clamp_min, (Range{0, 1, true}), "OctoMap lower clamping"),
      CLEANMAP_FIELD_IN("clamp_max", map.clamp_max, (Range{0, 1, true}), "OctoMap upper clamping"),
      CLEANMAP_FIELD_IN("insert_voxel", map.insert_voxel, kNonNegative, "Downsampling before ray casting, m; 0 = resolution"),
      CLEANMAP_FIELD_IN("free_probability", map.free_probability, kShare, "Cells at most this likely occupied count as free"),
      CLEANMAP_FIELD_IN("insert_every", insert_every, kAtLeastOne, "Ray-cast every k-th scan into the OctoMap"),
      CLEANMAP_FIELD_IN("cloud_voxel", cloud_voxel, kNonNegative, "Voxel filter of the static cloud, m (0 = all points)"),
      CLEANMAP_FIELD("write_raw_map", write_raw_map, "Also write map_raw.pcd (no removal)"),
      CLEANMAP_FIELD("free_space", free_space, "Add the free-space opinion (hits in observed-free cells)"),
      CLEANMAP_FIELD_IN("free_space_fraction", free_space_objects.min_fraction, kShare, "Share of a cluster in free space that makes it dynamic"),
      CLEANMAP_FIELD_IN("free_space_min_hits", free_space_objects.min_votes, (Range{1, 1e6}), "Voxels (free_space_voxel) of a cluster that must lie in free space"),
      CLEANMAP_FIELD_IN("free_space_voxel", free_space_voxel, (Range{0.001, 100}), "Free-space votes: subsample voxel, one vote each, m"),
      CLEANMAP_FIELD_IN("free_space_min_split_radius", free_space_objects.min_split_radius, kPositive, "Free-space vote: over-large clusters are re-clustered down to this radius, m"),
      CLEANMAP_FIELD_IN("free_space_cluster_radius", free_space_objects.radius, kPositive, "Free-space vote: clustering distance, m"),
      CLEANMAP_FIELD_IN("free_space_max_extent", free_space_objects.max_extent, kPositive, "Free-space vote: wider clusters are split, m"),
      CLEANMAP_FIELD_IN("visibility_resolution", visibility.resolution, (Range{0.001, 100}), "Offline: cells of the log-wide visibility map, m"),
      CLEANMAP_FIELD_IN("visibility_margin", visibility.margin, kNonNegative, "Offline: rays stop this short of their hit, m"),
      CLEANMAP_FIELD_IN("visibility_extent_margin", visibility.extent_margin, kNonNegative,
                        "Offline: a ray crosses a cell where it passes this close to the box of the cell's hits, m"),
      CLEANMAP_FIELD_IN("visibility_angular_margin", visibility.angular_margin, kNonNegative,
                        "Offline: a ray goes through a cell's hits only past their level by this times its range, rad"),
      CLEANMAP_FIELD_IN("visibility_max_range", visibility.max_range, kPositive, "Offline: longer rays are not cast, m"),
      CLEANMAP_FIELD("occupancy_grid", occupancy_grid, "Write a 2D occupancy grid (PGM + YAML)"),
      CLEANMAP_FIELD_IN("grid_z_min", grid_z_min, kAny, "Lowest height above the local ground in the 2D grid, m"),
      CLEANMAP_FIELD_IN("grid_z_max", grid_z_max, kAny, "Highest height above the local ground in the 2D grid, m"));
}

inline YAML::Node load_optional_preset(const std::filesystem::path& file) {
  return file.empty() ? YAML::Node() : load_preset(file);
}

// Every setting of one streaming pass, by preset section.
struct PipelineConfig {
  InputSettings input;
  OdometryConfig odometry;
  ScorerConfig scorer;
  MappingSettings mapping;
};

// The preset sections of a PipelineConfig (bits): "input" is always there; a command takes the
// others it needs, and the ones it does not take keep their defaults.
enum Section { kOdometry = 1, kScorer = 2, kMapping = 4 };

// Defaults <- the preset file's sections (those in `sections`), each key checked.
PipelineConfig config_from_preset(const YAML::Node& preset, const std::filesystem::path& file, int sections);

}  // namespace cleanmap::pipeline
