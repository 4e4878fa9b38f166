#pragma once

// Shared by the fuzz targets: inputs become a file (the readers under test take paths), and
// only cleanmap::Error may end a read; anything else (a crash, a sanitizer report, another
// exception, a hang, an allocation beyond -rss_limit_mb) is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/error.hpp"

namespace cleanmap::fuzz {

// A per-process file in /dev/shm (memory, not disk) holding the input.
inline std::filesystem::path as_file(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  static const std::filesystem::path path =
      std::filesystem::path("/dev/shm") / ("cleanmap-fuzz-" + std::to_string(getpid()) + ext);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                               static_cast<std::streamsize>(size));
  return path;
}

template <typename F>
void expect_clean(F&& read) {
  try {
    read();
  } catch (const Error&) {
    // a clear error naming the input: what bad input must get
  }
}

}  // namespace cleanmap::fuzz
