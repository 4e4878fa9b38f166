#include "io/sequence.hpp"

#include <algorithm>
#include <map>

#include "io/error.hpp"
#include "io/kitti_bin.hpp"
#include "io/label_file.hpp"
#include "io/depth_sequence.hpp"
#include "io/ros2_bag.hpp"
#ifdef CLEANMAP_WITH_ROSBAG
#include "io/rosbag_source.hpp"
#endif

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

bool is_scan_file(const fs::path& p) {
  const auto ext = p.extension().string();
  return ext == ".bin" || ext == ".pcd" || ext == ".ply";
}

std::vector<fs::path> list_scans(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && is_scan_file(entry.path())) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void check_count(const fs::path& file, std::size_t have, std::size_t want, const char* what) {
  if (have != want) {
    fail(file, "has " + std::to_string(have) + " " + what + " but the sequence has " +
                   std::to_string(want) + " scans");
  }
}

}  // namespace

bool Sequence::has_labels() const {
  return std::any_of(labels.begin(), labels.end(), [](const fs::path& p) { return !p.empty(); });
}

namespace {

// Times and poses of a bag (ROS 1 or 2): its message stamps, and a pose topic or a pose file.
template <typename Source>
Sequence bag_sequence(const fs::path& root, std::shared_ptr<const Source> bag, const char* layout,
                      const SequenceOptions& options) {
  Sequence seq;
  seq.root = root;
  seq.layout = layout;
  seq.cloud = options.cloud;
  for (std::size_t i = 0; i < bag->size(); ++i) {
    seq.scans.push_back(fs::path(scan_name(i)));
  }
  seq.labels.resize(bag->size());
  seq.times = bag->stamps();
  seq.times_source = "bag " + bag->topic() + " header stamps";
  if (!options.poses_file.empty()) {
    const auto stamped = read_poses(options.poses_file, options.pose_format);
    check_count(options.poses_file, stamped.size(), bag->size(), "poses");
    for (const auto& p : stamped) seq.poses.push_back(p.pose);
    seq.poses_source = options.poses_file.string();
  } else if (!bag->poses().empty()) {
    seq.poses = bag->poses();
    seq.poses_source = "bag " + options.bag_pose_topic;
  }
  for (std::size_t i = 1; i < seq.times.size(); ++i) {
    if (!(seq.times[i] > seq.times[i - 1])) fail(root, "message stamps must increase (message " + std::to_string(i) + ")");
  }
  seq.read_scan = [bag](std::size_t index, TimeUnit unit) { return bag->read(index, unit); };
  return seq;
}

BagOptions bag_options(const SequenceOptions& o) { return {o.bag_topic, o.bag_pose_topic, o.bag_child_frame}; }

Sequence open_bag(const fs::path& file, const SequenceOptions& options) {
#ifdef CLEANMAP_WITH_ROSBAG
  return bag_sequence<BagSource>(file, std::make_shared<const BagSource>(file, bag_options(options)), "rosbag", options);
#else
  (void)options;
  fail(file, "this build of cleanmap has no ROS bag support (configure with CLEANMAP_WITH_ROSBAG=ON)");
#endif
}

// The sequence's poses (options.poses_file, else FOLDER/poses.txt, if any; KITTI camera-frame
// poses turned into the lidar frame with calib.txt's Tr), as read.
std::vector<StampedPose> attach_poses(Sequence& seq, const fs::path& folder, const SequenceOptions& options) {
  std::vector<StampedPose> stamped;
  fs::path poses_file = options.poses_file;
  if (poses_file.empty() && fs::exists(folder / "poses.txt")) poses_file = folder / "poses.txt";
  if (poses_file.empty()) return stamped;
  stamped = read_poses(poses_file, options.pose_format);
  check_count(poses_file, stamped.size(), seq.scans.size(), "poses");
  const bool kitti = std::isnan(stamped.front().stamp);
  const bool to_lidar = kitti && seq.calib_tr && options.kitti_poses_in_camera_frame;
  for (const auto& p : stamped) {
    seq.poses.push_back(to_lidar ? Eigen::Isometry3d(seq.calib_tr->inverse() * p.pose * *seq.calib_tr) : p.pose);
  }
  seq.poses_source = poses_file.string() + (to_lidar ? " (camera frame -> lidar via Tr)" : "");
  return stamped;
}

// The scans' times: options.times_file or FOLDER/times.txt, else the poses' stamps, else the
// scan rate. They must increase.
void attach_times(Sequence& seq, const fs::path& folder, const SequenceOptions& options,
                  const std::vector<StampedPose>& stamped) {
  const std::size_t n = seq.scans.size();
  fs::path times_file = options.times_file;
  if (times_file.empty() && fs::exists(folder / "times.txt")) times_file = folder / "times.txt";
  if (!times_file.empty()) {
    seq.times = read_times(times_file);
    check_count(times_file, seq.times.size(), n, "times");
    seq.times_source = times_file.string();
  } else if (!stamped.empty() && !std::isnan(stamped.front().stamp)) {
    for (const auto& p : stamped) seq.times.push_back(p.stamp);
    seq.times_source = "pose stamps";
  } else {
    if (!(options.rate_hz > 0.0)) throw Error("scan rate must be positive");
    for (std::size_t i = 0; i < n; ++i) seq.times.push_back(static_cast<double>(i) / options.rate_hz);
    seq.times_source = "rate " + std::to_string(options.rate_hz) + " Hz";
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (!(seq.times[i] > seq.times[i - 1])) {
      fail(times_file.empty() ? folder : times_file, "scan times must increase (scan " + std::to_string(i) + ")");
    }
  }
}

}  // namespace

Sequence open_sequence(const fs::path& folder, const SequenceOptions& options) {
  // (issue 45: `--input ''` said only ": no such folder")
  if (folder.empty()) throw Error("input: empty path (name a log folder, or a .bag file)");
  if (folder.extension() == ".bag") return open_bag(folder, options);
  if (is_tum_rgbd(folder)) return open_tum_rgbd(folder, options);
  if (is_ros2_bag(folder)) {
    return bag_sequence<Ros2BagSource>(folder, std::make_shared<const Ros2BagSource>(folder, bag_options(options)),
                                       "ros2bag", options);
  }
  if (!fs::exists(folder)) fail(folder, "no such folder");
  if (!fs::is_directory(folder)) fail(folder, "is not a folder");
  for (const auto& e : fs::directory_iterator(folder)) {
    const auto ext = e.path().extension();
    if (ext == ".db3" || ext == ".mcap") {
      fail(folder, "holds " + e.path().filename().string() + " but no metadata.yaml: not a complete ROS 2 bag "
                   "folder (`ros2 bag reindex FOLDER` writes it)");
    }
  }
  Sequence seq;
  seq.root = folder;
  seq.cloud = options.cloud;
  fs::path scan_dir = folder;
  if (fs::is_directory(folder / "velodyne")) {
    seq.layout = "kitti";
    scan_dir = folder / "velodyne";
  } else if (fs::is_directory(folder / "pcd")) {
    seq.layout = "dynamicmap";
    seq.world_frame = true;
    scan_dir = folder / "pcd";
  } else if (fs::is_directory(folder / "scans")) {
    seq.layout = "scans-folder";
    scan_dir = folder / "scans";
  } else {
    seq.layout = "plain-folder";
  }
  seq.scans = list_scans(scan_dir);
  if (seq.scans.empty()) fail(scan_dir, "contains no scan files (.bin, .pcd, .ply)");
  const std::size_t n = seq.scans.size();

  seq.labels.resize(n);
  if (fs::is_directory(folder / "labels")) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = folder / "labels" / (seq.scans[i].stem().string() + ".label");
      if (fs::exists(p)) seq.labels[i] = p;
    }
  }

  if (fs::exists(folder / "calib.txt")) seq.calib_tr = read_kitti_calib_tr(folder / "calib.txt");

  const auto stamped = attach_poses(seq, folder, options);
  attach_times(seq, folder, options, stamped);
  check_unique_names(seq);
  return seq;
}

void check_unique_names(const Sequence& seq) {
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < seq.scans.size(); ++i) {
    const auto [it, fresh] = first.try_emplace(seq.scans[i].stem().string(), i);
    if (!fresh) {
      fail(seq.root, "scans " + seq.scans[it->second].lexically_relative(seq.root).string() + " and " +
                         seq.scans[i].lexically_relative(seq.root).string() + " share the name '" + it->first +
                         "': their outputs (labels/" + it->first + ".label, ...) would overwrite each other; rename one");
    }
  }
}

Scan read_scan_file(const fs::path& file, const CloudReadOptions& options) {
  if (file.extension() == ".bin") return read_kitti_bin(file);
  return read_cloud(file, options);
}

Scan read_raw_scan(const Sequence& seq, std::size_t index) {
  return seq.read_scan ? seq.read_scan(index, seq.cloud.time_unit) : read_scan_file(seq.scans.at(index), seq.cloud);
}

Eigen::Vector3d local_origin_near(const Eigen::Vector3d& first_position) {
  if (!first_position.allFinite()) return Eigen::Vector3d::Zero();
  return (first_position / 1000.0).array().round().matrix() * 1000.0;
}

Eigen::Vector3d automatic_local_origin(const Sequence& seq) {
  if (seq.has_poses()) return local_origin_near(seq.poses.front().translation());
  if (!seq.world_frame || seq.size() == 0) return Eigen::Vector3d::Zero();  // odometry: its own frame
  const Scan first = read_raw_scan(seq, 0);
  if (first.pose) return local_origin_near(first.pose->translation());
  for (Eigen::Index i = 0; i < first.points.cols(); ++i) {
    if (first.points.col(i).allFinite()) return local_origin_near(first.points.col(i).cast<double>());
  }
  return Eigen::Vector3d::Zero();
}

void set_local_origin(Sequence& seq, const Eigen::Vector3d& origin) {
  const Eigen::Vector3d change = origin - seq.origin;
  for (auto& pose : seq.poses) pose.translation() -= change;
  seq.origin = origin;
  if (seq.world_frame) seq.cloud.shift = origin;
}

LoadedScan load_scan(const Sequence& seq, std::size_t index) {
  LoadedScan out;
  out.scan = read_raw_scan(seq, index);
  Scan& scan = out.scan;
  if (!seq.labels[index].empty()) {
    out.labels = read_labels(seq.labels[index], scan.size());
  }
  // Per-point times read as epoch offsets are re-expressed relative to the sequence's stamp.
  if (scan.has_time() && scan.stamp != 0.0) {
    scan.time.array() += static_cast<float>(scan.stamp - seq.times[index]);
  }
  scan.stamp = seq.times[index];
  if (seq.has_poses()) scan.pose = seq.poses[index];
  if (seq.world_frame && !scan.pose) {  // VIEWPOINT at the frame's origin (or none given)
    scan.pose = Eigen::Isometry3d(Eigen::Translation3d(-seq.origin));
    out.viewpoint_missing = true;
  }
  const DroppedPoints dropped = drop_invalid(scan);
  out.dropped_non_finite = dropped.non_finite;
  out.dropped_out_of_range = dropped.out_of_range;
  if (dropped.non_finite + dropped.out_of_range > 0 && !out.labels.empty()) {
    std::vector<std::uint32_t> kept(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) kept[i] = out.labels[scan.input_index[i]];
    out.labels = std::move(kept);
  }
  return out;
}

}  // namespace cleanmap
