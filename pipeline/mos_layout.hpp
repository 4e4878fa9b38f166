#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap::pipeline {

// Predictions in the SemanticKITTI moving-object-segmentation benchmark's layout,
// OUT/sequences/XX/predictions/NNNNNN.label, so that `sequences/` can be zipped and submitted
// as it is: one uint32 per point of the velodyne file, 251 moving and 9 static. The benchmark
// has no "not scored": points cleanmap did not score, masked as the platform or dropped as NaN
// are static there (labels/ keeps them as 0).
//
// The folder for `input`: XX is `sequence` when given, else the input folder's name when it is
// a number (`.../sequences/8` or `08` -> 08); otherwise an Error asks for --mos-sequence.
std::filesystem::path mos_predictions_dir(const std::filesystem::path& out, const std::filesystem::path& input,
                                          const std::string& sequence);

// The file of one scan: its own name when that is the benchmark's six digits (a KITTI
// velodyne/NNNNNN.bin), else its index in the log, six digits.
std::filesystem::path mos_label_file(const std::filesystem::path& dir, const Scan& scan, std::size_t index);

// 251 / 9 per point, in input order (dropped points static).
std::vector<std::uint32_t> mos_labels(const Scan& scan, const std::vector<std::uint8_t>& dynamic);

}  // namespace cleanmap::pipeline
