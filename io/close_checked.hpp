#pragma once

#include <filesystem>
#include <fstream>

#include "io/error.hpp"

namespace cleanmap {

// Closes a file written through `out` and fails naming `file` when any write to it failed. A
// stream keeps its last few kilobytes until it is closed, so for a small file a full disk
// shows only here: checking the stream before closing it reported labels, poses and maps
// complete that a full disk had cut short (tests `*.AFullDisk*`, on /dev/full).
inline void close_checked(std::ofstream& out, const std::filesystem::path& file) {
  out.close();
  if (!out) fail(file, "write failed (disk full?)");
}

}  // namespace cleanmap
