#include "io/ros2_bag.hpp"

#include <zstd.h>

#include <fstream>
#include <functional>
#include <set>

#include "io/close_checked.hpp"
#include "io/error.hpp"
#include "io/mcap_file.hpp"
#include "io/raw_cloud.hpp"
#include "io/ros2_messages.hpp"
#include "io/sqlite_bag.hpp"
#include "io/yaml_file.hpp"
#include "io/zstd_frame.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

constexpr const char* kCloudType = "sensor_msgs/msg/PointCloud2";
constexpr std::size_t kHeadBytes = 4096;  // a header's stamp and frame id: enough to list the scans

YAML::Node child(const YAML::Node& n, const char* key, const fs::path& file) {
  if (!n.IsMap() || !n[key]) fail(file, std::string("has no '") + key + "' (not a rosbag2 metadata file?)");
  return n[key];
}

// The bytes of a message as stored, undoing rosbag2's per-message zstd compression.
std::vector<std::uint8_t> unpacked(std::vector<std::uint8_t> bytes, bool zstd, const std::string& what) {
  if (!zstd) return bytes;
  return unzstd_frame(bytes.data(), bytes.size(), 0, kMaxChunkExpansion, what);
}

// The poses one message of a pose topic carries (a TFMessage: several).
std::vector<StampedTransform> decode_poses(const std::string& type, const std::vector<std::uint8_t>& m,
                                           const std::string& what) {
  if (type == "nav_msgs/msg/Odometry") return {decode_odometry(m.data(), m.size(), what)};
  if (type == "geometry_msgs/msg/TransformStamped") return {decode_transform_stamped(m.data(), m.size(), what)};
  return decode_tf_message(m.data(), m.size(), what);
}

}  // namespace

bool is_ros2_bag(const fs::path& folder) {
  std::error_code ec;
  return fs::is_directory(folder, ec) && fs::is_regular_file(folder / "metadata.yaml", ec);
}

Ros2BagInfo read_ros2_metadata(const fs::path& folder) {
  const fs::path file = folder / "metadata.yaml";
  const YAML::Node root = load_yaml_file(file, "no metadata.yaml: not a ROS 2 bag folder (`ros2 bag reindex` writes one)");
  Ros2BagInfo info;
  try {
    const YAML::Node b = child(root, "rosbag2_bagfile_information", file);
    info.storage = child(b, "storage_identifier", file).as<std::string>();
    if (info.storage != "sqlite3" && info.storage != "mcap") {
      fail(file, "storage '" + info.storage + "' is not read (cleanmap reads sqlite3 and mcap bags)");
    }
    for (const auto& p : child(b, "relative_file_paths", file)) info.files.push_back(folder / p.as<std::string>());
    if (info.files.empty()) fail(file, "lists no storage files (relative_file_paths)");
    if (b["topics_with_message_count"]) {
      for (const auto& t : b["topics_with_message_count"]) {
        const YAML::Node m = child(t, "topic_metadata", file);
        info.topics[child(m, "name", file).as<std::string>()] = child(m, "type", file).as<std::string>();
      }
    }
    if (b["compression_format"]) info.compression_format = b["compression_format"].as<std::string>();
    if (b["compression_mode"]) info.compression_mode = b["compression_mode"].as<std::string>();
  } catch (const YAML::Exception& e) {
    fail(file, std::string("has a field of the wrong kind (") + e.what() + ")");
  }
  const bool compressed = !info.compression_format.empty() && info.compression_mode != "" && info.compression_mode != "NONE";
  if (compressed && (info.compression_format != "zstd" || (info.compression_mode != "MESSAGE" && info.compression_mode != "message"))) {
    fail(file, "compression " + info.compression_mode + " / " + info.compression_format +
                   " is not read (per-message zstd is): `ros2 bag decompress` it first");
  }
  return info;
}

void write_ros2_metadata(const fs::path& folder, const std::string& storage, const std::vector<std::string>& files,
                         const std::vector<Ros2TopicCount>& topics, std::int64_t start_ns, std::int64_t duration_ns) {
  YAML::Emitter y;
  std::size_t total = 0;
  for (const auto& t : topics) total += t.count;
  y << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "version" << YAML::Value << 5 << YAML::Key << "storage_identifier" << YAML::Value << storage;
  y << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds" << YAML::Value << duration_ns
    << YAML::EndMap;
  y << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch"
    << YAML::Value << start_ns << YAML::EndMap;
  y << YAML::Key << "message_count" << YAML::Value << total;
  y << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const auto& t : topics) {
    y << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap << YAML::Key << "name"
      << YAML::Value << t.name << YAML::Key << "type" << YAML::Value << t.type << YAML::Key << "serialization_format"
      << YAML::Value << "cdr" << YAML::Key << "offered_qos_profiles" << YAML::Value << "" << YAML::EndMap
      << YAML::Key << "message_count" << YAML::Value << t.count << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::Key << "compression_format" << YAML::Value << "" << YAML::Key << "compression_mode"
    << YAML::Value << "" << YAML::Key << "relative_file_paths" << YAML::Value << files << YAML::EndMap << YAML::EndMap;
  std::ofstream out(folder / "metadata.yaml");
  out << y.c_str() << "\n";
  close_checked(out, folder / "metadata.yaml");
}

// The bag's storage files and where each wanted message lies in them.
struct Ros2BagSource::Impl {
  struct Ref {
    std::size_t file = 0;
    std::int64_t row = 0;  // sqlite3
    McapMessageRef mcap;   // mcap
  };
  std::vector<std::unique_ptr<SqliteBagReader>> sqlite;
  std::vector<std::unique_ptr<McapReader>> mcap;
  std::vector<fs::path> files;  // the storage files, as sqlite / mcap hold them
  bool zstd_messages = false;
  std::vector<Ref> clouds;

  using Visit = std::function<void(const std::string& topic, const Ref&, std::int64_t time_ns, std::vector<std::uint8_t> head)>;
  // Every message on `topics` (with at least `kHeadBytes` of it, all of it for `whole`), file by file.
  void visit(const std::set<std::string>& topics, const std::string& whole, const Visit& on) {
    for (std::size_t f = 0; f < sqlite.size(); ++f) {
      for (const auto& topic : topics) {
        std::vector<std::vector<std::uint8_t>> heads;
        const bool all = topic == whole || zstd_messages;  // a compressed head cannot be cut
        const auto rows = sqlite[f]->rows(topic, all ? 0 : kHeadBytes, &heads);
        for (std::size_t k = 0; k < rows.size(); ++k) on(topic, {f, rows[k].id, {}}, rows[k].timestamp, std::move(heads[k]));
      }
    }
    for (std::size_t f = 0; f < mcap.size(); ++f) {
      mcap[f]->scan(topics, [&](const McapChannel& c, const McapMessageRef& m, const std::uint8_t* d, std::size_t n) {
        if (c.message_encoding != "cdr") {
          fail(files[f], "channel " + std::to_string(c.id) + " (" + c.topic + ") has message encoding '" +
                             c.message_encoding + "': rosbag2 writes cdr, the only encoding read here");
        }
        const std::size_t keep = c.topic == whole ? n : std::min(n, kHeadBytes);
        on(c.topic, {f, 0, m}, static_cast<std::int64_t>(m.log_time), std::vector<std::uint8_t>(d, d + keep));
      });
    }
  }

  std::vector<std::uint8_t> fetch(const Ref& r, const std::string& what) const {
    return unpacked(sqlite.empty() ? mcap[r.file]->read(r.mcap) : sqlite[r.file]->read(r.row), zstd_messages, what);
  }
};

Ros2BagSource::Ros2BagSource(const fs::path& folder, const BagOptions& options)
    : impl_(std::make_unique<Impl>()), folder_(folder), info_(read_ros2_metadata(folder)) {
  impl_->zstd_messages = !info_.compression_format.empty();
  for (const auto& f : info_.files) {
    impl_->files.push_back(f);
    if (info_.storage == "sqlite3") impl_->sqlite.push_back(std::make_unique<SqliteBagReader>(f));
    else impl_->mcap.push_back(std::make_unique<McapReader>(f));
  }
  topic_ = options.cloud_topic;
  if (topic_.empty()) {
    std::set<std::string> candidates;
    for (const auto& [name, type] : info_.topics) {
      if (type == kCloudType) candidates.insert(name);
    }
    if (candidates.size() != 1) {
      fail(folder, std::to_string(candidates.size()) + " " + kCloudType + " topics in metadata.yaml; name one with --bag-topic");
    }
    topic_ = *candidates.begin();
  }
  auto type = info_.topics.find(topic_);
  if (type == info_.topics.end()) fail(folder, "has no topic " + topic_ + " (metadata.yaml)");
  if (type->second != kCloudType) fail(folder, "topic " + topic_ + " carries " + type->second + ", not " + kCloudType);
  const std::string& pose_topic = options.pose_topic;
  std::string pose_type;
  if (!pose_topic.empty()) {
    auto p = info_.topics.find(pose_topic);
    if (p == info_.topics.end()) fail(folder, "has no pose topic " + pose_topic + " (metadata.yaml)");
    pose_type = p->second;
    if (pose_type != "nav_msgs/msg/Odometry" && pose_type != "geometry_msgs/msg/TransformStamped" &&
        pose_type != "tf2_msgs/msg/TFMessage") {
      fail(folder, "pose topic " + pose_topic + " carries " + pose_type +
                       " (expected nav_msgs/msg/Odometry, geometry_msgs/msg/TransformStamped or tf2_msgs/msg/TFMessage)");
    }
  }
  std::map<double, Eigen::Isometry3d> track;
  std::size_t pose_index = 0;
  std::set<std::string> wanted{topic_};
  if (!pose_topic.empty()) wanted.insert(pose_topic);
  try {
    impl_->visit(wanted, pose_topic, [&](const std::string& topic, const Impl::Ref& ref, std::int64_t t_ns, std::vector<std::uint8_t> head) {
      const std::string what = folder.string() + ": " + topic + " message";
      head = unpacked(std::move(head), impl_->zstd_messages, what);
      if (topic == topic_) {
        const double stamp = decode_header_stamp(head.data(), head.size(), what);
        stamps_.push_back(stamp != 0.0 ? stamp : 1e-9 * static_cast<double>(t_ns));
        impl_->clouds.push_back(ref);
        if (topic != pose_topic) return;
      }
      for (const auto& p : decode_poses(pose_type, head, what)) {
        if (pose_type == "tf2_msgs/msg/TFMessage" && !options.child_frame.empty() && p.child_frame_id != options.child_frame) continue;
        const auto pose = checked_pose(p.rotation, p.translation);
        if (!pose) {
          fail(folder, "pose topic " + pose_topic + ", message " + std::to_string(pose_index) +
                           ": not a finite pose (NaN, infinite or zero-length quaternion)");
        }
        track[p.stamp] = *pose;
      }
      ++pose_index;
    });
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(folder, std::string("unreadable bag (") + e.what() + ")");
  }
  if (impl_->clouds.empty()) fail(folder, "no messages on topic " + topic_);
  if (!pose_topic.empty()) {
    if (track.empty()) fail(folder, "no poses on topic " + pose_topic + (options.child_frame.empty() ? "" : " for frame " + options.child_frame));
    check_coverage(folder, track, stamps_, "scan", "the pose topic " + pose_topic + " does not cover the clouds (trim the bag, or run without given poses)");
    for (double t : stamps_) poses_.push_back(pose_at(track, t));
  }
}

Ros2BagSource::~Ros2BagSource() = default;

Scan Ros2BagSource::read(std::size_t index, TimeUnit time_unit) const {
  const std::string source = folder_.string() + ":" + topic_ + "#" + std::to_string(index);
  const auto bytes = impl_->fetch(impl_->clouds.at(index), source);
  const PointCloud2Msg msg = decode_point_cloud2(bytes.data(), bytes.size(), source);
  std::vector<std::uint8_t> swapped;
  Scan scan = scan_from_raw_cloud(raw_cloud_of(msg, swapped, source), source, time_unit);
  scan.name = scan_name(index);
  // Per-point times relative to the message stamp unless they were absolute (the sequence
  // handles those like any epoch-stamped scan).
  if (scan.stamp == 0.0) scan.stamp = stamps_[index];
  return scan;
}

}  // namespace cleanmap
