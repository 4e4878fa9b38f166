#include "io/cloud_file.hpp"

#include <limits>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <fstream>
#include <sstream>

#include "io/close_checked.hpp"
#include "io/error.hpp"
#include "io/pcd_file.hpp"
#include "io/ply_file.hpp"
#include "io/raw_cloud.hpp"

namespace cleanmap {
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// PCL refuses to write a cloud without points; an empty map is still a valid result (a log in
// which everything moved), so its header is written here: the same fields, 0 points.
void write_empty_cloud(const std::filesystem::path& file, const std::vector<std::string>& fields,
                       const std::string& ext, const Eigen::Vector4f& origin, const Eigen::Quaternionf& q) {
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file, "cannot create file");
  if (ext == ".pcd") {
    out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
    for (const auto& f : fields) out << ' ' << f;
    out << "\nSIZE";
    for (std::size_t k = 0; k < fields.size(); ++k) out << " 4";
    out << "\nTYPE";
    for (std::size_t k = 0; k < fields.size(); ++k) out << " F";
    out << "\nCOUNT";
    for (std::size_t k = 0; k < fields.size(); ++k) out << " 1";
    out << "\nWIDTH 0\nHEIGHT 1\nVIEWPOINT " << origin[0] << ' ' << origin[1] << ' ' << origin[2] << ' ' << q.w() << ' '
        << q.x() << ' ' << q.y() << ' ' << q.z() << "\nPOINTS 0\nDATA binary\n";
  } else if (ext == ".ply") {
    out << "ply\nformat binary_little_endian 1.0\nelement vertex 0\n";
    for (const auto& f : fields) out << "property float " << f << '\n';
    out << "end_header\n";
  } else {
    fail(file, "unsupported cloud extension '" + ext + "' (expected .pcd or .ply)");
  }
  close_checked(out, file);
}

// Through a stream, not PCL's file writers: those map the file into memory, and on a full disk
// the copy into the mapping killed the run with SIGBUS (PCL 1.13, a 30 MB tmpfs as --out),
// where a stream's write fails and says so. PCL still makes the header and the compressed body
// (in memory: its stream writer, given a file stream that failed, threw std::bad_cast).
void write_pcd(const std::filesystem::path& file, const pcl::PCLPointCloud2& cloud,
               const Eigen::Vector4f& origin, const Eigen::Quaternionf& orientation,
               bool compressed) {
  pcl::PCDWriter writer;
  std::ostringstream packed;
  if (compressed && writer.writeBinaryCompressed(packed, cloud, origin, orientation) < 0)
    fail(file, "write failed");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) fail(file, "cannot create file");
  if (compressed) {
    out << packed.str();
  } else {
    out << writer.generateHeaderBinary(cloud, origin, orientation) << "DATA binary\n";
    out.write(reinterpret_cast<const char*>(cloud.data.data()),
              static_cast<std::streamsize>(cloud.data.size()));
  }
  close_checked(out, file);
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
  const auto ext = lower(file.extension().string());
  CloudRecords records;
  if (ext == ".pcd") {
    records = read_pcd(file);
  } else if (ext == ".ply") {
    records = read_ply(file);
  } else {
    if (!std::filesystem::is_regular_file(file)) fail(file, "no such file");
    fail(file, "unsupported cloud extension '" + ext + "' (expected .pcd or .ply)");
  }
  Scan scan = scan_from_raw_cloud(records.view(), file, options.time_unit, options.shift);
  scan.name = file.stem().string();
  if (records.viewpoint) {
    scan.pose = records.viewpoint;
    scan.pose->translation() -= options.shift;
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
  PackedCloud cloud;
  for (const auto& f : fields) cloud.fields.push_back(f.first);
  cloud.data.resize(4 * fields.size() * scan.size());
  auto* out = reinterpret_cast<float*>(cloud.data.data());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    float* row = out + i * fields.size();
    row[0] = scan.points(0, static_cast<Eigen::Index>(i));
    row[1] = scan.points(1, static_cast<Eigen::Index>(i));
    row[2] = scan.points(2, static_cast<Eigen::Index>(i));
    for (std::size_t k = 3; k < fields.size(); ++k) row[k] = fields[k].second[i];
  }
  write_packed_cloud(file, cloud, options);
}

void write_packed_cloud(const std::filesystem::path& file, PackedCloud& packed, const CloudWriteOptions& options) {
  const std::size_t step = 4 * packed.fields.size();
  if (packed.fields.size() < 3 || packed.data.size() % step != 0 ||
      packed.data.size() / step > std::numeric_limits<std::uint32_t>::max()) {
    fail(file, "cannot write a cloud of " + std::to_string(packed.data.size()) + " bytes in rows of " +
                   std::to_string(packed.fields.size()) + " fields");
  }
  pcl::PCLPointCloud2 cloud;
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(packed.data.size() / step);
  cloud.is_dense = false;
  cloud.point_step = static_cast<std::uint32_t>(step);
  cloud.row_step = cloud.point_step * cloud.width;
  for (std::size_t k = 0; k < packed.fields.size(); ++k) {
    pcl::PCLPointField f;
    f.name = packed.fields[k];
    f.offset = static_cast<std::uint32_t>(4 * k);
    f.datatype = pcl::PCLPointField::FLOAT32;
    f.count = 1;
    cloud.fields.push_back(f);
  }
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  if (options.viewpoint) {
    origin.head<3>() = options.viewpoint->translation().cast<float>();
    orientation = Eigen::Quaternionf(options.viewpoint->rotation().cast<float>());
  }
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const auto ext = lower(file.extension().string());
  if (cloud.width == 0) {
    write_empty_cloud(file, packed.fields, ext, origin, orientation);
    return;
  }
  // The bytes go to PCL's cloud for the write and come back whatever happens.
  cloud.data.swap(packed.data);
  struct GiveBack {
    std::vector<std::uint8_t>& a;
    std::vector<std::uint8_t>& b;
    ~GiveBack() { a.swap(b); }
  } give_back{cloud.data, packed.data};
  if (ext == ".pcd") {
    write_pcd(file, cloud, origin, orientation, options.compressed);
  } else if (ext == ".ply") {
    // PCL's PLY writer does not look at its stream after writing: a file shorter than its
    // points (a full disk) is caught here.
    std::error_code ec;
    if (pcl::PLYWriter().writeBinary(file.string(), cloud, origin, orientation, true) < 0 ||
        std::filesystem::file_size(file, ec) < cloud.data.size() || ec) {
      fail(file, "write failed (disk full?)");
    }
  } else {
    fail(file, "unsupported cloud extension '" + ext + "' (expected .pcd or .ply)");
  }
}

}  // namespace cleanmap
