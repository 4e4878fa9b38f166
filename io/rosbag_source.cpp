#include "io/rosbag_source.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <map>
#include <set>

#include "io/error.hpp"
#include "io/pose_file.hpp"
#include "io/raw_cloud.hpp"

namespace cleanmap {
namespace {

std::optional<Eigen::Isometry3d> to_pose(const geometry_msgs::Transform& t) {
  return checked_pose(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z),
                      Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
}

std::optional<Eigen::Isometry3d> to_pose(const geometry_msgs::Pose& t) {
  return checked_pose(Eigen::Quaterniond(t.orientation.w, t.orientation.x, t.orientation.y, t.orientation.z),
                      Eigen::Vector3d(t.position.x, t.position.y, t.position.z));
}

}  // namespace

struct BagSource::Impl {
  rosbag::Bag bag;
  std::vector<rosbag::MessageInstance> clouds;
};

BagSource::BagSource(const std::filesystem::path& file, const BagOptions& options)
    : impl_(std::make_unique<Impl>()), file_(file) {
  if (!std::filesystem::is_regular_file(file)) fail(file, "no such bag file");
  try {
    impl_->bag.open(file.string(), rosbag::bagmode::Read);
    topic_ = options.cloud_topic;
    if (topic_.empty()) {
      std::set<std::string> candidates;
      rosbag::View all(impl_->bag);
      for (const auto* c : all.getConnections()) {
        if (c->datatype == "sensor_msgs/PointCloud2") candidates.insert(c->topic);
      }
      if (candidates.size() != 1) {
        fail(file, std::to_string(candidates.size()) +
                       " PointCloud2 topics in the bag; name one with --bag-topic");
      }
      topic_ = *candidates.begin();
    }
    rosbag::View view(impl_->bag, rosbag::TopicQuery(topic_));
    for (const auto& m : view) {
      if (m.getDataType() != "sensor_msgs/PointCloud2") {
        fail(file, "topic " + topic_ + " carries " + m.getDataType() + ", not sensor_msgs/PointCloud2");
      }
      const auto msg = m.instantiate<sensor_msgs::PointCloud2>();
      stamps_.push_back(msg->header.stamp.isZero() ? m.getTime().toSec() : msg->header.stamp.toSec());
      impl_->clouds.push_back(m);
    }
    if (impl_->clouds.empty()) fail(file, "no messages on topic " + topic_);

    if (!options.pose_topic.empty()) {
      std::map<double, Eigen::Isometry3d> track;
      rosbag::View poses(impl_->bag, rosbag::TopicQuery(options.pose_topic));
      std::size_t index = 0;
      auto add = [&](double stamp, const std::optional<Eigen::Isometry3d>& pose) {
        if (!pose) {
          fail(file, "pose topic " + options.pose_topic + ", message " + std::to_string(index) +
                         ": not a finite pose (NaN, infinite or zero-length quaternion)");
        }
        track[stamp] = *pose;
      };
      for (const auto& m : poses) {
        if (auto odom = m.instantiate<nav_msgs::Odometry>()) {
          add(odom->header.stamp.toSec(), to_pose(odom->pose.pose));
        } else if (auto tf = m.instantiate<geometry_msgs::TransformStamped>()) {
          add(tf->header.stamp.toSec(), to_pose(tf->transform));
        } else if (auto tfs = m.instantiate<tf2_msgs::TFMessage>()) {
          for (const auto& t : tfs->transforms) {
            if (options.child_frame.empty() || t.child_frame_id == options.child_frame) {
              add(t.header.stamp.toSec(), to_pose(t.transform));
            }
          }
        } else {
          fail(file, "pose topic " + options.pose_topic + " carries " + m.getDataType() +
                         " (expected nav_msgs/Odometry, geometry_msgs/TransformStamped or tf2_msgs/TFMessage)");
        }
        ++index;
      }
      if (track.empty()) fail(file, "no poses on topic " + options.pose_topic);
      check_coverage(file, track, stamps_, "scan", "the pose topic " + options.pose_topic + " does not cover the clouds (trim the bag, or run without given poses)");
      for (double t : stamps_) poses_.push_back(pose_at(track, t));
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(file, std::string("unreadable or truncated bag (") + e.what() + ")");
  }
}

BagSource::~BagSource() = default;

Scan BagSource::read(std::size_t index, TimeUnit time_unit) const {
  sensor_msgs::PointCloud2::ConstPtr msg;
  try {
    msg = impl_->clouds.at(index).instantiate<sensor_msgs::PointCloud2>();
  } catch (const std::exception& e) {
    fail(file_, "message " + std::to_string(index) + " on " + topic_ + " is unreadable (" + e.what() + ")");
  }
  if (!msg) fail(file_, "message " + std::to_string(index) + " on " + topic_ + " is not a PointCloud2");
  if (msg->is_bigendian) fail(file_, "big-endian point clouds are not supported");
  const std::size_t n = static_cast<std::size_t>(msg->width) * msg->height;
  const auto source = file_.string() + ":" + topic_ + "#" + std::to_string(index);
  RawCloud raw;
  std::vector<std::uint8_t> packed;
  // scan_from_raw_cloud checks the layout against raw.bytes
  raw.data = packed_rows(msg->data.data(), msg->data.size(), msg->width, msg->height, msg->point_step, msg->row_step,
                         packed, source, raw.bytes);
  raw.points = n;
  raw.point_step = msg->point_step;
  for (const auto& f : msg->fields) raw.fields.push_back({f.name, f.offset, f.datatype});
  Scan scan = scan_from_raw_cloud(raw, source, time_unit);
  scan.name = scan_name(index);
  // Per-point times relative to the message stamp unless they were absolute (handled by the
  // sequence like any epoch-stamped scan).
  if (scan.stamp == 0.0) scan.stamp = stamps_[index];
  return scan;
}

}  // namespace cleanmap
