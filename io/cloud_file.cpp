#include "io/cloud_file.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <array>
#include <cmath>
#include <cstring>
#include <optional>

#include "io/error.hpp"

namespace cleanmap {
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const pcl::PCLPointField* find_field(const pcl::PCLPointCloud2& cloud,
                                     std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (const auto& f : cloud.fields) {
      if (lower(f.name) == name) return &f;
    }
  }
  return nullptr;
}

double read_value(const std::uint8_t* p, std::uint8_t type) {
  switch (type) {
    case pcl::PCLPointField::INT8: { std::int8_t v; std::memcpy(&v, p, 1); return v; }
    case pcl::PCLPointField::UINT8: return *p;
    case pcl::PCLPointField::INT16: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::UINT16: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::INT32: { std::int32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::UINT32: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::INT64: { std::int64_t v; std::memcpy(&v, p, 8); return static_cast<double>(v); }
    case pcl::PCLPointField::UINT64: { std::uint64_t v; std::memcpy(&v, p, 8); return static_cast<double>(v); }
    case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, p, 8); return v; }
    default: return std::nan("");
  }
}

bool known_type(std::uint8_t type) {
  return type >= pcl::PCLPointField::INT8 && type <= pcl::PCLPointField::UINT64;
}

// Reads one field of every point as double.
std::vector<double> column(const pcl::PCLPointCloud2& cloud, const pcl::PCLPointField& f,
                           const std::filesystem::path& file) {
  if (!known_type(f.datatype)) {
    fail(file, "field '" + f.name + "' has unknown type code " + std::to_string(f.datatype));
  }
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = read_value(cloud.data.data() + i * cloud.point_step + f.offset, f.datatype);
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

TimeUnit parse_time_unit(const std::string& text) {
  if (text == "auto") return TimeUnit::kAuto;
  if (text == "s") return TimeUnit::kSeconds;
  if (text == "ms") return TimeUnit::kMilliseconds;
  if (text == "us") return TimeUnit::kMicroseconds;
  if (text == "ns") return TimeUnit::kNanoseconds;
  throw Error("unknown time unit '" + text + "' (expected auto, s, ms, us or ns)");
}

Scan read_cloud(const std::filesystem::path& file, const CloudReadOptions& options) {
  if (!std::filesystem::is_regular_file(file)) fail(file, "no such file");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  const auto ext = lower(file.extension().string());
  int version = 0;
  int rc = -1;
  try {
    if (ext == ".pcd") {
      pcl::PCDReader reader;
      // PCL maps a binary body without checking its length: check it against the header first.
      int data_type = 0;
      unsigned int data_idx = 0;
      if (reader.readHeader(file.string(), cloud, origin, orientation, version, data_type,
                            data_idx) < 0) {
        fail(file, "invalid PCD header");
      }
      const std::uintmax_t need =
          data_idx + static_cast<std::uintmax_t>(cloud.width) * cloud.height * cloud.point_step;
      const auto have = std::filesystem::file_size(file);
      if (data_type == 1 && have < need) {
        fail(file, "truncated: binary data ends at byte " + std::to_string(have) + ", header needs " +
                       std::to_string(need));
      }
      rc = reader.read(file.string(), cloud, origin, orientation, version);
    } else if (ext == ".ply") {
      rc = pcl::PLYReader().read(file.string(), cloud, origin, orientation, version);
    } else {
      fail(file, "unsupported cloud extension '" + ext + "' (expected .pcd or .ply)");
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(file, std::string("unreadable ") + ext + " file (" + e.what() + ")");
  }
  if (rc < 0) fail(file, "unreadable or truncated " + ext + " file (header or data invalid)");
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (cloud.data.size() < n * cloud.point_step) fail(file, "data shorter than its header says");

  const auto* fx = find_field(cloud, {"x"});
  const auto* fy = find_field(cloud, {"y"});
  const auto* fz = find_field(cloud, {"z"});
  if (!fx || !fy || !fz) fail(file, "has no x, y, z fields");
  for (const auto& f : cloud.fields) {
    if (!known_type(f.datatype)) {
      fail(file, "field '" + f.name + "' has unknown type code " + std::to_string(f.datatype));
    }
  }

  Scan scan;
  scan.name = file.stem().string();
  scan.input_size = n;
  scan.points.resize(3, static_cast<Eigen::Index>(n));
  const std::array<const pcl::PCLPointField*, 3> xyz{fx, fy, fz};
  for (int d = 0; d < 3; ++d) {
    const auto values = column(cloud, *xyz[d], file);
    for (std::size_t i = 0; i < n; ++i) scan.points(d, static_cast<Eigen::Index>(i)) = static_cast<float>(values[i]);
  }

  if (const auto* fi = find_field(cloud, {"intensity", "remission", "reflectivity", "i"})) {
    const auto v = column(cloud, *fi, file);
    scan.intensity = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(n)).cast<float>();
  } else if (const auto* frgb = find_field(cloud, {"rgb", "rgba"})) {
    // A grey value packed into the colour bytes of a float: take the red byte.
    scan.intensity.resize(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t packed;
      std::memcpy(&packed, cloud.data.data() + i * cloud.point_step + frgb->offset, 4);
      scan.intensity[static_cast<Eigen::Index>(i)] = static_cast<float>((packed >> 16) & 0xFFu);
    }
  }

  if (const auto* ft = find_field(cloud, {"t", "time", "timestamp", "stamp"})) {
    auto v = column(cloud, *ft, file);
    double lo = INFINITY, hi = -INFINITY;
    for (double x : v) {
      if (std::isfinite(x)) { lo = std::min(lo, x); hi = std::max(hi, x); }
    }
    if (n > 0 && std::isfinite(lo)) {
      const double scale = options.time_unit == TimeUnit::kAuto ? detect_time_scale(hi - lo)
                                                               : unit_scale(options.time_unit);
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

  if (!origin.head<3>().isZero() || !orientation.coeffs().isApprox(Eigen::Quaternionf::Identity().coeffs())) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = orientation.cast<double>().normalized().toRotationMatrix();
    pose.translation() = origin.head<3>().cast<double>();
    scan.pose = pose;
  }
  return scan;
}

void write_cloud(const std::filesystem::path& file, const Scan& scan,
                 const std::vector<CloudField>& extra, const CloudWriteOptions& options) {
  std::vector<std::pair<std::string, const float*>> fields{
      {"x", nullptr}, {"y", nullptr}, {"z", nullptr}};
  if (scan.has_intensity()) fields.emplace_back("intensity", scan.intensity.data());
  if (scan.has_time()) fields.emplace_back("t", scan.time.data());
  for (const auto& f : extra) {
    if (f.values.size() != scan.size()) {
      fail(file, "field '" + f.name + "' has " + std::to_string(f.values.size()) +
                     " values for " + std::to_string(scan.size()) + " points");
    }
    fields.emplace_back(f.name, f.values.data());
  }
  pcl::PCLPointCloud2 cloud;
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(scan.size());
  cloud.is_dense = false;
  cloud.point_step = static_cast<std::uint32_t>(4 * fields.size());
  cloud.row_step = cloud.point_step * cloud.width;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    pcl::PCLPointField f;
    f.name = fields[k].first;
    f.offset = static_cast<std::uint32_t>(4 * k);
    f.datatype = pcl::PCLPointField::FLOAT32;
    f.count = 1;
    cloud.fields.push_back(f);
  }
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  auto* out = reinterpret_cast<float*>(cloud.data.data());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    float* row = out + i * fields.size();
    row[0] = scan.points(0, static_cast<Eigen::Index>(i));
    row[1] = scan.points(1, static_cast<Eigen::Index>(i));
    row[2] = scan.points(2, static_cast<Eigen::Index>(i));
    for (std::size_t k = 3; k < fields.size(); ++k) row[k] = fields[k].second[i];
  }
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  if (options.viewpoint) {
    origin.head<3>() = options.viewpoint->translation().cast<float>();
    orientation = Eigen::Quaternionf(options.viewpoint->rotation().cast<float>());
  }
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const auto ext = lower(file.extension().string());
  int rc = -1;
  if (ext == ".pcd") {
    pcl::PCDWriter writer;
    rc = options.compressed ? writer.writeBinaryCompressed(file.string(), cloud, origin, orientation)
                    : writer.writeBinary(file.string(), cloud, origin, orientation);
  } else if (ext == ".ply") {
    rc = pcl::PLYWriter().writeBinary(file.string(), cloud, origin, orientation, true);
  } else {
    fail(file, "unsupported cloud extension '" + ext + "' (expected .pcd or .ply)");
  }
  if (rc < 0) fail(file, "write failed");
}

}  // namespace cleanmap
