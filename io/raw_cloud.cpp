#include "io/raw_cloud.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "io/error.hpp"

namespace cleanmap {
namespace {

enum : std::uint8_t { kInt8 = 1, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64, kInt64, kUint64 };

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const RawField* find_field(const RawCloud& cloud, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (const auto& f : cloud.fields) {
      if (lower(f.name) == name) return &f;
    }
  }
  return nullptr;
}

template <typename T>
double load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double value_of(const std::uint8_t* p, std::uint8_t type) {
  switch (type) {
    case kInt8: return load<std::int8_t>(p);
    case kUint8: return load<std::uint8_t>(p);
    case kInt16: return load<std::int16_t>(p);
    case kUint16: return load<std::uint16_t>(p);
    case kInt32: return load<std::int32_t>(p);
    case kUint32: return load<std::uint32_t>(p);
    case kFloat32: return load<float>(p);
    case kFloat64: return load<double>(p);
    case kInt64: return load<std::int64_t>(p);
    case kUint64: return load<std::uint64_t>(p);
    default: return std::nan("");
  }
}

// One field of every point, as double.
std::vector<double> column(const RawCloud& cloud, const RawField& f) {
  std::vector<double> out(cloud.points);
  for (std::size_t i = 0; i < cloud.points; ++i) {
    out[i] = value_of(cloud.data + i * cloud.point_step + f.offset, f.datatype);
  }
  return out;
}

double unit_scale(TimeUnit unit) {
  switch (unit) {
    case TimeUnit::kMilliseconds: return 1e-3;
    case TimeUnit::kMicroseconds: return 1e-6;
    case TimeUnit::kNanoseconds: return 1e-9;
    default: return 1.0;
  }
}

// A spinning sensor's sweep lasts 0.05-0.2 s and a depth frame far less: the largest unit in
// which the spread of the times is at most one second is the unit they were written in.
double detect_time_scale(double spread) {
  for (double scale : {1.0, 1e-3, 1e-6, 1e-9}) {
    if (spread * scale <= 1.0) return scale;
  }
  return 1e-9;
}

}  // namespace

double read_value(const std::uint8_t* p, std::uint8_t datatype) { return value_of(p, datatype); }

std::uint32_t type_size(std::uint8_t datatype) {
  switch (datatype) {
    case kInt8: case kUint8: return 1;
    case kInt16: case kUint16: return 2;
    case kInt32: case kUint32: case kFloat32: return 4;
    case kFloat64: case kInt64: case kUint64: return 8;
    default: return 0;
  }
}

namespace {

template <typename T>
bool store_integer(double value, std::uint8_t* out) {
  // 2^63 and 2^64 are exact doubles; the limits of the narrower types are too.
  const double lo = static_cast<double>(std::numeric_limits<T>::min());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  if (!(value >= lo && value <= hi) || value != std::floor(value)) return false;
  const T v = value >= hi ? std::numeric_limits<T>::max() : static_cast<T>(value);
  std::memcpy(out, &v, sizeof(T));
  return true;
}

}  // namespace

bool store_value(double value, std::uint8_t datatype, std::uint8_t* out) {
  switch (datatype) {
    case kInt8: return store_integer<std::int8_t>(value, out);
    case kUint8: return store_integer<std::uint8_t>(value, out);
    case kInt16: return store_integer<std::int16_t>(value, out);
    case kUint16: return store_integer<std::uint16_t>(value, out);
    case kInt32: return store_integer<std::int32_t>(value, out);
    case kUint32: return store_integer<std::uint32_t>(value, out);
    case kInt64: return store_integer<std::int64_t>(value, out);
    case kUint64: return store_integer<std::uint64_t>(value, out);
    case kFloat32: {
      const float v = static_cast<float>(value);
      std::memcpy(out, &v, 4);
      return true;
    }
    case kFloat64: std::memcpy(out, &value, 8); return true;
    default: return false;
  }
}

const std::uint8_t* packed_rows(const std::uint8_t* data, std::size_t bytes, std::uint32_t width,
                                std::uint32_t height, std::uint32_t point_step, std::uint32_t row_step,
                                std::vector<std::uint8_t>& storage, const std::string& source,
                                std::size_t& packed_bytes) {
  const std::uint64_t row = std::uint64_t{width} * point_step;
  packed_bytes = bytes;
  // A row of no bytes (no points, or a point step of 0) has nothing to pack; copying it
  // would hand memcpy the empty storage's null pointer (UBSan, fuzz_ros2_cdr).
  if (height <= 1 || row_step == row || row == 0) return data;
  if (row_step < row) {
    fail(source, "row_step " + std::to_string(row_step) + " is shorter than a row's " + std::to_string(width) +
                     " points of " + std::to_string(point_step) + " bytes");
  }
  // Both factors come from the message: the last row needs only its points.
  if (std::uint64_t{row_step} * (height - 1) + row > bytes) {
    fail(source, "data holds " + std::to_string(bytes) + " bytes, fewer than " + std::to_string(height) +
                     " rows of row_step " + std::to_string(row_step) + " need");
  }
  storage.resize(static_cast<std::size_t>(row) * height);
  for (std::uint32_t r = 0; r < height; ++r) {
    std::memcpy(storage.data() + static_cast<std::size_t>(row) * r, data + static_cast<std::size_t>(row_step) * r,
                static_cast<std::size_t>(row));
  }
  packed_bytes = storage.size();
  return storage.data();
}

Scan scan_from_raw_cloud(const RawCloud& cloud, const std::filesystem::path& source,
                         TimeUnit time_unit, const Eigen::Vector3d& shift) {
  for (const auto& f : cloud.fields) {
    if (f.datatype < kInt8 || f.datatype > kUint64) {
      fail(source, "field '" + f.name + "' has unknown type code " + std::to_string(f.datatype));
    }
    if (static_cast<std::uint64_t>(f.offset) + type_size(f.datatype) > cloud.point_step) {
      fail(source, "field '" + f.name + "' (offset " + std::to_string(f.offset) + ", " +
                       std::to_string(type_size(f.datatype)) + " bytes) lies beyond the point step of " +
                       std::to_string(cloud.point_step) + " bytes");
    }
  }
  // Both factors come from a header: compare by division, a product could wrap.
  if (cloud.points > 0 && (cloud.point_step == 0 || cloud.bytes / cloud.point_step < cloud.points)) {
    fail(source, "data holds " + std::to_string(cloud.bytes) + " bytes, fewer than " +
                     std::to_string(cloud.points) + " points of " + std::to_string(cloud.point_step) +
                     " bytes need");
  }
  const auto* fx = find_field(cloud, {"x"});
  const auto* fy = find_field(cloud, {"y"});
  const auto* fz = find_field(cloud, {"z"});
  if (!fx || !fy || !fz) fail(source, "has no x, y, z fields");
  const std::size_t n = cloud.points;
  Scan scan;
  scan.input_size = n;
  scan.points.resize(3, static_cast<Eigen::Index>(n));
  const std::array<const RawField*, 3> xyz{fx, fy, fz};
  for (int d = 0; d < 3; ++d) {
    const auto values = column(cloud, *xyz[d]);
    for (std::size_t i = 0; i < n; ++i) {
      scan.points(d, static_cast<Eigen::Index>(i)) = static_cast<float>(values[i] - shift[d]);
    }
  }
  if (const auto* fi = find_field(cloud, {"intensity", "remission", "reflectivity", "i"})) {
    const auto v = column(cloud, *fi);
    scan.intensity = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(n)).cast<float>();
  } else if (const auto* frgb = find_field(cloud, {"rgb", "rgba"}); frgb && type_size(frgb->datatype) == 4) {
    // A grey value packed into the colour bytes of a float: take the red byte.
    scan.intensity.resize(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t packed;
      std::memcpy(&packed, cloud.data + i * cloud.point_step + frgb->offset, 4);
      scan.intensity[static_cast<Eigen::Index>(i)] = static_cast<float>((packed >> 16) & 0xFFu);
    }
  }
  if (const auto* ft = find_field(cloud, {"t", "time", "timestamp", "stamp"})) {
    const auto v = column(cloud, *ft);
    double lo = INFINITY, hi = -INFINITY;
    for (double x : v) {
      if (std::isfinite(x)) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
    if (n > 0 && std::isfinite(lo)) {
      const double scale = time_unit == TimeUnit::kAuto ? detect_time_scale(hi - lo) : unit_scale(time_unit);
      // Epoch times: keep the first point's time as the stamp and store offsets from it, so
      // float32 per-point times keep microsecond precision.
      const double origin_time = (lo * scale > 1e5) ? lo : 0.0;
      scan.stamp = origin_time * scale;
      scan.time.resize(static_cast<Eigen::Index>(n));
      for (std::size_t i = 0; i < n; ++i) {
        scan.time[static_cast<Eigen::Index>(i)] = static_cast<float>((v[i] - origin_time) * scale);
      }
    }
  }
  return scan;
}

}  // namespace cleanmap
