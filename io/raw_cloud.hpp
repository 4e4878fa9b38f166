#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/scan.hpp"

namespace cleanmap {

// A point record layout as PCD files and ROS sensor_msgs/PointCloud2 both describe it (they
// share the type codes 1 = int8 ... 8 = float64; PCL adds 9 = int64, 10 = uint64).
struct RawField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
};

struct RawCloud {
  std::vector<RawField> fields;
  const std::uint8_t* data = nullptr;  // points * point_step bytes, little-endian
  std::size_t points = 0;
  std::uint32_t point_step = 0;
};

// x, y, z (required), intensity (`intensity`, `remission`, `reflectivity`, `i`, or the grey
// value of a packed `rgb`) and per-point time (`t`, `time`, `timestamp`, `stamp`, unit detected
// from the spread unless given; epoch times become stamp + offsets). `source` names the input
// in errors.
Scan scan_from_raw_cloud(const RawCloud& cloud, const std::filesystem::path& source,
                         TimeUnit time_unit);

}  // namespace cleanmap
