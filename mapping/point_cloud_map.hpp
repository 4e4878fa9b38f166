#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <tsl/robin_set.h>
#include <vector>

#include "io/cloud_file.hpp"
#include "io/scan.hpp"
#include "io/voxel_key.hpp"

namespace cleanmap {

// A world-frame point cloud built scan by scan. With a voxel size, only the first point that
// falls in each voxel is kept (raw measurements, not voxel centres), so memory grows with the
// mapped area, not the log length.
class PointCloudMap {
 public:
  explicit PointCloudMap(double voxel_size = 0.0) : voxel_(voxel_size) {}

  // Adds the points of `scan` (world frame) with keep[i] != 0, carrying intensity, the
  // per-point score and the scan index as fields.
  void add(const Scan& scan, const std::vector<std::uint8_t>& keep,
           const std::vector<float>& score, std::size_t scan_index);

  std::size_t size() const { return x_.size(); }

  // Writes x y z [intensity] score scan (PCD or PLY by extension).
  void write(const std::filesystem::path& file) const;

 private:
  double voxel_;
  tsl::robin_set<VoxelKey, VoxelKeyHash> seen_;
  std::vector<float> x_, y_, z_, intensity_, score_, scan_;
  bool has_intensity_ = true;
};

}  // namespace cleanmap
