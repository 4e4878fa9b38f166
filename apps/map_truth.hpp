#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap::app {

// A DynamicMap ground truth (gt_cloud.pcd): every point with intensity 0 (static) or 1
// (dynamic). Any other value, or no intensity field, fails naming the file and the point.
struct MapTruth {
  Scan cloud;
  std::vector<std::uint8_t> dynamic;  // 1 per dynamic point
};
MapTruth read_map_truth(const std::filesystem::path& file);

}  // namespace cleanmap::app
