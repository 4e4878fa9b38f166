#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
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
  std::size_t bytes = 0;               // readable bytes at `data`
  std::size_t points = 0;
  std::uint32_t point_step = 0;
};

// An organised cloud's rows packed one after another. ROS's PointCloud2 may pad each row
// (row_step > width * point_step is legal; issue 45: such a cloud was read as if unpadded, every
// row after the first shifted). Copies into `storage` only when the rows are padded; throws
// Error naming `source` when row_step is shorter than a row's points or the data cannot hold
// its rows.
const std::uint8_t* packed_rows(const std::uint8_t* data, std::size_t bytes, std::uint32_t width,
                                std::uint32_t height, std::uint32_t point_step, std::uint32_t row_step,
                                std::vector<std::uint8_t>& storage, const std::string& source,
                                std::size_t& packed_bytes);

// Records read from a file (PCD, PLY), owning their bytes.
struct CloudRecords {
  std::vector<RawField> fields;
  std::vector<std::uint8_t> data;
  std::size_t points = 0;
  std::uint32_t point_step = 0;
  std::optional<Eigen::Isometry3d> viewpoint;  // the sensor pose the file states, if any
  RawCloud view() const { return {fields, data.data(), data.size(), points, point_step}; }
};

// The little-endian value at `p` of a type code, as double (NaN for an unknown code).
double read_value(const std::uint8_t* p, std::uint8_t datatype);

// Bytes of one value of a type code (0 for an unknown code).
std::uint32_t type_size(std::uint8_t datatype);

// Stores `value` at `out` as the type code's little-endian value; false when it does not fit
// (not an integer, or out of range, for the integer types).
bool store_value(double value, std::uint8_t datatype, std::uint8_t* out);

// Checks the layout first (a point step, every field inside it, the bytes for every point: a
// lying PointCloud2 or file header fails here, naming `source`), then reads x, y, z (required), intensity (`intensity`, `remission`, `reflectivity`, `i`, or the grey
// value of a packed `rgb`) and per-point time (`t`, `time`, `timestamp`, `stamp`, unit detected
// from the spread unless given; epoch times become stamp + offsets). `source` names the input
// in errors. `shift` is subtracted from x, y, z in double before they become float.
Scan scan_from_raw_cloud(const RawCloud& cloud, const std::filesystem::path& source,
                         TimeUnit time_unit, const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

}  // namespace cleanmap
