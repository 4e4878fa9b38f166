#pragma once

#include <filesystem>
#include <vector>

namespace cleanmap {

// Per-point float32 values (dynamic scores; NaN = not scored), in input order, no header.
std::vector<float> read_scores(const std::filesystem::path& file, std::size_t expected_points = 0);
void write_scores(const std::filesystem::path& file, const std::vector<float>& scores);

}  // namespace cleanmap
