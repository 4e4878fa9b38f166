#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap {

enum class TimeUnit { kAuto, kSeconds, kMilliseconds, kMicroseconds, kNanoseconds };

// Parses "auto", "s", "ms", "us", "ns"; throws Error on anything else.
TimeUnit parse_time_unit(const std::string& text);

struct CloudReadOptions {
  TimeUnit time_unit = TimeUnit::kAuto;
  // Subtracted from x, y, z (and the VIEWPOINT's position) in double, before they become
  // float: a world-frame cloud at georeferenced coordinates (UTM: millions of metres, where a
  // float keeps a 0.5 m grid) keeps the file's precision relative to the map's local origin.
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

// Reads a PCD (ascii, binary, binary_compressed; any field layout) or PLY (ascii, binary) file
// with the project's own readers (pcd_file, ply_file), which check every declared size first.
// x, y, z are required. Intensity comes from `intensity`, `remission`, `reflectivity`, `i`, or
// the grey value of a packed `rgb`. Per-point time from `t`, `time`, `timestamp`, `stamp`; its
// unit is detected from the spread of the values (a sweep lasts well under a second) unless
// given; absolute times (epoch) become `stamp` plus relative times. A PCD VIEWPOINT (or PLY
// camera) other than identity becomes the scan's pose. NaN points are kept; callers drop them.
Scan read_cloud(const std::filesystem::path& file, const CloudReadOptions& options = {});

// A float32 per-point field to write beside x, y, z (e.g. "score", "label", "scan").
struct CloudField {
  std::string name;
  std::vector<float> values;
};

struct CloudWriteOptions {
  bool compressed = false;  // PCD binary_compressed instead of binary
  // Written as the PCD VIEWPOINT (sensor pose in the frame of the points): set it for clouds in
  // the world frame, leave it empty for clouds in the sensor frame.
  std::optional<Eigen::Isometry3d> viewpoint;
};

// Writes x y z [intensity] [t] [extra fields] as float32: binary PCD or binary PLY, chosen by
// the extension.
void write_cloud(const std::filesystem::path& file, const Scan& scan,
                 const std::vector<CloudField>& extra = {}, const CloudWriteOptions& options = {});

// Points already packed as rows of float32 fields (x, y, z first): what write_cloud makes of a
// Scan, for a caller that holds its points that way (a map cloud of millions of points: one
// packed copy instead of a Scan, its fields and then the rows).
struct PackedCloud {
  std::vector<std::string> fields;  // x, y, z, then the rest
  std::vector<std::uint8_t> data;   // fields.size() float32 per point, point after point
};

// Writes `cloud` as write_cloud does. Its bytes are lent to PCL's cloud while the file is
// written and handed back (also when writing fails), so one packed copy serves several files.
void write_packed_cloud(const std::filesystem::path& file, PackedCloud& cloud, const CloudWriteOptions& options = {});

}  // namespace cleanmap
