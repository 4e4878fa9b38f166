#include "pipeline/progress.hpp"

#include <unistd.h>

#include <cstdio>

#include "pipeline/interrupt.hpp"

namespace cleanmap::pipeline {

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

double Progress::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(std::size_t done) {
  done_ = done;
  // Every long loop reports here once per scan: the place to stop when asked to.
  throw_if_interrupted(std::to_string(done) + " of " + std::to_string(total_) + " scans (" + label_ + ")");
  if (!tty_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_print_ < std::chrono::milliseconds(100)) return;
  last_print_ = now;
  const double t = elapsed_s();
  const double rate = t > 0 ? static_cast<double>(done) / t : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - done) / rate : 0.0;
  std::fprintf(stderr, "\r%s  %zu/%zu scans  %.1f scans/s  ETA %.0f s   ", label_.c_str(), done,
               total_, rate, eta);
  std::fflush(stderr);
}

void Progress::finish() {
  // Time only: the command's last line gives the one rate that counts, over the whole run.
  if (tty_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s: %zu scans in %.1f s\n", label_.c_str(), done_, elapsed_s());
}

}  // namespace cleanmap::pipeline
