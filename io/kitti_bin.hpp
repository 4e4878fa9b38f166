#pragma once

#include <filesystem>

#include "io/scan.hpp"

namespace cleanmap {

// KITTI Velodyne format: float32 x, y, z, remission per point, no header.
Scan read_kitti_bin(const std::filesystem::path& file);
void write_kitti_bin(const std::filesystem::path& file, const Scan& scan);

}  // namespace cleanmap
