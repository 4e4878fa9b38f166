#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "io/error.hpp"

namespace cleanmap::test {

inline std::filesystem::path shared_data() { return CLEANMAP_SHARED_DATA; }
inline std::filesystem::path source_dir() { return CLEANMAP_SOURCE_DIR; }

// A fresh folder under the system temp dir, removed at scope exit.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() /
           ("cleanmap-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::filesystem::path operator/(const std::string& name) const { return path / name; }
};

// Asserts that `fn` throws cleanmap::Error whose message contains every fragment.
inline void expect_error(const std::function<void()>& fn,
                         std::initializer_list<std::string> fragments) {
  try {
    fn();
    ADD_FAILURE() << "expected cleanmap::Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) {
      EXPECT_NE(msg.find(f), std::string::npos) << "message '" << msg << "' lacks '" << f << "'";
    }
  }
}

// Runs the cleanmap binary with `args`; returns its exit code, stdout and stderr in `output`.
inline int run_cleanmap(const std::string& args, std::string* output = nullptr) {
  const std::string cmd = std::string(CLEANMAP_BINARY) + " " + args + " 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::fgets(buf, sizeof(buf), p)) out += buf;
  if (output) *output = out;
  return WEXITSTATUS(pclose(p));
}

// Exit code and everything printed of one cleanmap command.
struct CliResult {
  int code;
  std::string output;
};

inline CliResult cli(const std::string& args) {
  CliResult r;
  r.code = run_cleanmap(args, &r.output);
  return r;
}

}  // namespace cleanmap::test
