#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace cleanmap::pipeline {

// "label  12/300 scans  9.8 scans/s  ETA 29 s" on one refreshed line when stderr is a
// terminal; silent otherwise (logs and CI), apart from the final line.
class Progress {
 public:
  Progress(std::string label, std::size_t total);
  void update(std::size_t done);
  void finish();
  double elapsed_s() const;

 private:
  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace cleanmap::pipeline
