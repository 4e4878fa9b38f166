#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace cleanmap {

// Moving-object-segmentation convention of SemanticKITTI (lower 16 bits of each uint32 label;
// the upper 16 hold an instance id).
inline constexpr std::uint32_t kLabelUnscored = 0;
inline constexpr std::uint32_t kLabelStatic = 9;
inline constexpr std::uint32_t kLabelMoving = 251;

inline std::uint32_t semantic_class(std::uint32_t label) { return label & 0xFFFFu; }
inline std::uint32_t instance_id(std::uint32_t label) { return label >> 16; }

// True for MOS "moving" (251) and the SemanticKITTI moving classes 252-259.
inline bool is_moving_label(std::uint32_t label) {
  const auto c = semantic_class(label);
  return c >= 251 && c <= 259;
}

// Reads a .label file; `expected_points` (the scan's point count, 0 included) is checked when
// given.
std::vector<std::uint32_t> read_labels(const std::filesystem::path& file,
                                       std::optional<std::size_t> expected_points = std::nullopt);
void write_labels(const std::filesystem::path& file, const std::vector<std::uint32_t>& labels);

}  // namespace cleanmap
