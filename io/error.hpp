#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace cleanmap {

// The one error type of the project: its message names the input and the problem, so the
// command line can print it as a single line and exit non-zero.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void fail(const std::filesystem::path& file, const std::string& problem) {
  throw Error(file.string() + ": " + problem);
}

}  // namespace cleanmap
