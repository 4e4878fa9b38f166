#pragma once

#include <filesystem>
#include <string_view>

#include "io/raw_cloud.hpp"

namespace cleanmap {

// Reads a PCD file (v0.5-0.7; DATA ascii, binary or binary_compressed) without PCL's reader,
// which crashed on empty and random files and allocated what a header claimed. Every size the
// header declares is checked against the file's length before anything is allocated for it,
// ascii values must be numbers that fit their field's type, rows must be complete, and the
// VIEWPOINT finite. Errors name the file and, for the body, the line.
CloudRecords read_pcd(const std::filesystem::path& file);

// The same from bytes in memory (`name` only labels errors): what the fuzz target calls.
CloudRecords parse_pcd(std::string_view bytes, const std::filesystem::path& name);

}  // namespace cleanmap
