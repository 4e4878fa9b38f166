// Scoring + upsampling per scan on a 131,072-ray stream (Ouster OS1-64 size: 64 x 2048 at
// 10 Hz, synthetic street), N = 10, d_r = 0.3, the paper's relative d_v.
//   build/bench/scorer_bench --benchmark_counters_tabular=true
#include <tbb/global_control.h>

#include <chrono>

#include "bench/bench_support.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"
#include "geometry/voxel_downsample.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "odometry/deskew.hpp"

namespace cleanmap {
namespace {

const std::vector<Scan>& os1_stream() {
  static const std::vector<Scan> scans = [] {
    LidarModel lidar;  // 64 x 2048
    const auto world = make_street_world(7);
    return to_world(simulate_sequence(world, lidar, 41, 7).scans);
  }();
  return scans;
}

void scorer(benchmark::State& state, const char* mode, double voxel_size) {
  tbb::global_control cores(tbb::global_control::max_allowed_parallelism, 2);
  const auto& scans = os1_stream();
  std::vector<double> per_scan;
  std::size_t rays = 0;
  for (auto _ : state) {
    ScorerConfig cfg;  // N = 10, d_r = 0.3, thr = 0.25
    cfg.mode = mode;
    cfg.voxel_size = voxel_size;
    SpatiotemporalScorer s(cfg);
    for (const auto& scan : scans) {
      for (auto& r : s.push(scan)) {
        if (r.scans_before == cfg.window_half && r.scans_after == cfg.window_half) per_scan.push_back(r.seconds);
        rays = r.scan.size();
      }
    }
  }
  state.counters["points_per_scan"] = static_cast<double>(rays);
  bench::report_latency(state, per_scan);
}

// The scorer's first step on each scan (and the visibility map's, the free-space vote's):
// every point to its voxel's kept point. One thread, the stream's scans in turn.
void downsample(benchmark::State& state, double voxel_size) {
  const auto& scans = os1_stream();
  std::size_t kept = 0, points = 0;
  for (auto _ : state) {
    for (const auto& scan : scans) {
      const double voxel = voxel_size > 0 ? voxel_size : bounding_box_diagonal(scan.points) / 600.0;
      const auto v = voxel_downsample_with_owners(scan.points, voxel);
      kept += v.keep.size();
      points += v.owner.size();
      benchmark::DoNotOptimize(v.owner.data());
    }
  }
  state.counters["kept_share"] = static_cast<double>(kept) / static_cast<double>(points);
  state.counters["ns_per_point"] = benchmark::Counter(static_cast<double>(points),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK_CAPTURE(downsample, relative_voxel, 0.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(downsample, voxel_0_2, 0.2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(scorer, fast_relative_voxel, "fast", 0.0)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(scorer, exact_relative_voxel, "exact", 0.0)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(scorer, fast_voxel_0_1, "fast", 0.1)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(scorer, exact_voxel_0_1, "exact", 0.1)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace cleanmap

BENCHMARK_MAIN();
