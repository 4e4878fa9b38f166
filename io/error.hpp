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

// A std::filesystem error as one line naming its path and the problem ("/data/log: permission
// denied"), not the library's "filesystem error: directory iterator cannot open directory: ...
// [path]" (issue 45: an unreadable folder was reported as "internal error: filesystem error").
inline std::string describe(const std::filesystem::filesystem_error& e) {
  std::string problem = e.code().message();
  if (!problem.empty() && problem[0] >= 'A' && problem[0] <= 'Z') problem[0] = static_cast<char>(problem[0] - 'A' + 'a');
  const std::string path = e.path1().empty() ? std::string("a file") : e.path1().string();
  return path + ": " + (problem.empty() ? std::string(e.what()) : problem);
}

[[noreturn]] inline void fail(const std::filesystem::path& file, const std::string& problem) {
  throw Error(file.string() + ": " + problem);
}

}  // namespace cleanmap
