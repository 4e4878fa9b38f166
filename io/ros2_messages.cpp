#include "io/ros2_messages.hpp"

#include <algorithm>
#include <cmath>

#include "io/cdr.hpp"
#include "io/error.hpp"

namespace cleanmap {
namespace {

struct Header {
  double stamp;
  std::string frame_id;
};

Header read_header(CdrReader& r) {
  const std::int32_t sec = r.i32();
  const std::uint32_t nanosec = r.u32();
  return {sec + 1e-9 * nanosec, r.string()};
}

void write_header(CdrWriter& w, double stamp, const std::string& frame_id) {
  const double sec = std::floor(stamp);
  w.i32(static_cast<std::int32_t>(sec));
  w.u32(static_cast<std::uint32_t>(std::min(999999999.0, std::round((stamp - sec) * 1e9))));
  w.string(frame_id);
}

// geometry_msgs Vector3/Point then Quaternion (x y z w), as both Pose and Transform lay them out.
void read_pose(CdrReader& r, StampedTransform& t) {
  for (int k = 0; k < 3; ++k) t.translation[k] = r.f64();
  t.rotation.x() = r.f64();
  t.rotation.y() = r.f64();
  t.rotation.z() = r.f64();
  t.rotation.w() = r.f64();
}

void write_pose(CdrWriter& w, const StampedTransform& t) {
  for (int k = 0; k < 3; ++k) w.f64(t.translation[k]);
  for (double v : {t.rotation.x(), t.rotation.y(), t.rotation.z(), t.rotation.w()}) w.f64(v);
}

StampedTransform read_transform_stamped(CdrReader& r) {
  StampedTransform t;
  const Header h = read_header(r);
  t.stamp = h.stamp;
  t.frame_id = h.frame_id;
  t.child_frame_id = r.string();
  read_pose(r, t);
  return t;
}

void write_transform_stamped(CdrWriter& w, const StampedTransform& t) {
  write_header(w, t.stamp, t.frame_id);
  w.string(t.child_frame_id);
  write_pose(w, t);
}

}  // namespace

double decode_header_stamp(const std::uint8_t* data, std::size_t size, const std::string& what) {
  CdrReader r(data, size, what);
  const std::int32_t sec = r.i32();
  return sec + 1e-9 * r.u32();
}

PointCloud2Msg decode_point_cloud2(const std::uint8_t* data, std::size_t size, const std::string& what) {
  CdrReader r(data, size, what + " (sensor_msgs/msg/PointCloud2)");
  PointCloud2Msg m;
  const Header h = read_header(r);
  m.stamp = h.stamp;
  m.frame_id = h.frame_id;
  m.height = r.u32();
  m.width = r.u32();
  const std::uint32_t n = r.count(13);  // a PointField is at least 4 + 1 + 4 + 1 + 4 bytes
  for (std::uint32_t k = 0; k < n; ++k) {
    RawField f;
    f.name = r.string();
    f.offset = r.u32();
    f.datatype = r.u8();
    (void)r.u32();  // count: cleanmap reads the first value of each field
    m.fields.push_back(f);
  }
  m.is_bigendian = r.boolean();
  m.point_step = r.u32();
  m.row_step = r.u32();
  m.data = r.bytes(m.data_size);
  m.is_dense = r.boolean();
  return m;
}

StampedTransform decode_odometry(const std::uint8_t* data, std::size_t size, const std::string& what) {
  CdrReader r(data, size, what + " (nav_msgs/msg/Odometry)");
  return read_transform_stamped(r);  // header, child_frame_id, then pose.pose: the same layout
}

StampedTransform decode_transform_stamped(const std::uint8_t* data, std::size_t size, const std::string& what) {
  CdrReader r(data, size, what + " (geometry_msgs/msg/TransformStamped)");
  return read_transform_stamped(r);
}

std::vector<StampedTransform> decode_tf_message(const std::uint8_t* data, std::size_t size, const std::string& what) {
  CdrReader r(data, size, what + " (tf2_msgs/msg/TFMessage)");
  const std::uint32_t n = r.count(4 + 4 + 5 + 5 + 56);  // header, child frame, 7 doubles
  std::vector<StampedTransform> out;
  for (std::uint32_t k = 0; k < n; ++k) out.push_back(read_transform_stamped(r));
  return out;
}

std::vector<std::uint8_t> encode_point_cloud2(const PointCloud2Msg& m, bool big_endian_cdr) {
  CdrWriter w(big_endian_cdr);
  write_header(w, m.stamp, m.frame_id);
  w.u32(m.height);
  w.u32(m.width);
  w.u32(static_cast<std::uint32_t>(m.fields.size()));
  for (const auto& f : m.fields) {
    w.string(f.name);
    w.u32(f.offset);
    w.u8(f.datatype);
    w.u32(1);
  }
  w.boolean(m.is_bigendian);
  w.u32(m.point_step);
  w.u32(m.row_step);
  w.bytes(m.data, m.data_size);
  w.boolean(m.is_dense);
  return w.data();
}

std::vector<std::uint8_t> encode_odometry(const StampedTransform& pose, bool big_endian_cdr) {
  CdrWriter w(big_endian_cdr);
  write_transform_stamped(w, pose);
  for (int k = 0; k < 36; ++k) w.f64(0.0);  // pose covariance
  for (int k = 0; k < 6 + 36; ++k) w.f64(0.0);  // twist and its covariance
  return w.data();
}

std::vector<std::uint8_t> encode_transform_stamped(const StampedTransform& t, bool big_endian_cdr) {
  CdrWriter w(big_endian_cdr);
  write_transform_stamped(w, t);
  return w.data();
}

std::vector<std::uint8_t> encode_tf_message(const std::vector<StampedTransform>& t, bool big_endian_cdr) {
  CdrWriter w(big_endian_cdr);
  w.u32(static_cast<std::uint32_t>(t.size()));
  for (const auto& x : t) write_transform_stamped(w, x);
  return w.data();
}

RawCloud raw_cloud_of(const PointCloud2Msg& m, std::vector<std::uint8_t>& storage, const std::string& source) {
  RawCloud raw;
  raw.fields = m.fields;
  raw.points = static_cast<std::size_t>(m.width) * m.height;
  raw.point_step = m.point_step;
  raw.data = packed_rows(m.data, m.data_size, m.width, m.height, m.point_step, m.row_step, storage, source, raw.bytes);
  if (!m.is_bigendian) return raw;
  // Each field's value reversed in a copy; a field that would not fit is left for
  // scan_from_raw_cloud's layout check to name.
  if (raw.data != storage.data()) storage.assign(raw.data, raw.data + raw.bytes);
  const std::size_t n = std::min(raw.points, m.point_step ? raw.bytes / m.point_step : 0);
  for (const auto& f : m.fields) {
    const std::uint32_t s = type_size(f.datatype);
    if (s <= 1 || std::uint64_t{f.offset} + s > m.point_step) continue;  // (64-bit: an offset near 2^32 wrapped)
    for (std::size_t i = 0; i < n; ++i) {
      std::uint8_t* v = storage.data() + i * m.point_step + f.offset;
      std::reverse(v, v + s);
    }
  }
  raw.data = storage.data();
  return raw;
}

}  // namespace cleanmap
