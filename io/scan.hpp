#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cleanmap {

// One sweep of a range sensor. Points are the columns of a 3xN matrix so that Eigen maps,
// nanoflann adaptors and TBB loops read them in place; per-point fields are parallel vectors.
struct Scan {
  Eigen::Matrix3Xf points;    // metres, sensor frame (or world frame once registered)
  Eigen::VectorXf time;       // seconds relative to `stamp`; empty when the sensor gives none
  Eigen::VectorXf intensity;  // empty when the input has none
  double stamp = 0.0;         // seconds; the time `pose` refers to
  std::optional<Eigen::Isometry3d> pose;  // sensor -> world at `stamp`, once known
  std::string name;           // file stem ("000123"); outputs for this scan reuse it

  // Position of each point in the file it came from, when points were dropped on reading
  // (NaNs); empty means point i is input point i. Per-point outputs are written in input order.
  std::vector<std::int32_t> input_index;
  std::size_t input_size = 0;  // number of points in the file

  std::size_t size() const { return static_cast<std::size_t>(points.cols()); }
  bool empty() const { return points.cols() == 0; }
  bool has_time() const { return time.size() == points.cols() && points.cols() > 0; }
  bool has_intensity() const { return intensity.size() == points.cols() && points.cols() > 0; }
};

// "000123": the six-digit zero-padded name of scan `index`, as KITTI numbers its files.
std::string scan_name(std::size_t index);

// Keeps the listed points (in the given order) in every per-point field, composing input_index.
Scan select_points(const Scan& scan, const std::vector<std::int32_t>& indices);

// What no sensor returns: a coordinate beyond 1e6 m from the scan's frame (sensor frame, or the
// map's local frame for world-frame input), or a point fired more than 10 s from its scan's
// stamp (sweeps last well under a second). Issue 45: a return 1e12 m away and a per-point time
// of 1e20 (epoch nanoseconds in a float field) were taken as they came and crashed the run
// (integer cell keys and time spans overflowed).
inline constexpr double kMaxCoordinate = 1e6, kMaxPointTime = 10.0;
struct DroppedPoints {
  std::size_t non_finite = 0;    // a NaN or infinite coordinate (or time)
  std::size_t out_of_range = 0;  // beyond kMaxCoordinate or kMaxPointTime
};
// Drops both kinds; returns how many of each.
DroppedPoints drop_invalid(Scan& scan);

// Scatters a per-point value back to input order; points dropped on reading get `fill`.
template <typename T>
std::vector<T> to_input_order(const Scan& scan, const std::vector<T>& values, T fill) {
  if (scan.input_index.empty()) {
    // Nothing dropped (or a scan made in memory); an all-NaN scan keeps no index but still
    // gets one value per input point.
    if (scan.size() > 0 || scan.input_size == 0) return values;
    return std::vector<T>(scan.input_size, fill);
  }
  std::vector<T> out(scan.input_size, fill);
  for (std::size_t i = 0; i < values.size(); ++i) out[scan.input_index[i]] = values[i];
  return out;
}

}  // namespace cleanmap
