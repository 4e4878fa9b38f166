#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace cleanmap::bench {

// Peak resident memory of this process so far, MiB (VmHWM).
inline double peak_rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0;
      status >> kib;
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

// Median and p99 of per-scan times (seconds) as counters in milliseconds.
inline void report_latency(benchmark::State& state, std::vector<double> seconds) {
  if (seconds.empty()) return;
  std::sort(seconds.begin(), seconds.end());
  state.counters["median_ms"] = 1e3 * seconds[seconds.size() / 2];
  state.counters["p99_ms"] = 1e3 * seconds[std::min(seconds.size() - 1, seconds.size() * 99 / 100)];
  state.counters["peak_rss_MiB"] = peak_rss_mib();
}

}  // namespace cleanmap::bench
