#pragma once

#include <filesystem>
#include <string_view>

#include "io/raw_cloud.hpp"

namespace cleanmap {

// Reads the vertex element of a PLY file (ascii, binary little- or big-endian) as records,
// without PCL's reader (which took non-numbers in ascii bodies as empty scans). Other elements
// are skipped (lists included); a `camera` element as PCL writes it gives the viewpoint. Every
// count is checked against the file's length before it is allocated or looped over.
CloudRecords read_ply(const std::filesystem::path& file);

// The same from bytes in memory (`name` only labels errors): what the fuzz target calls.
CloudRecords parse_ply(std::string_view bytes, const std::filesystem::path& name);

}  // namespace cleanmap
