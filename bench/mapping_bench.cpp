// Mapping per scan on a 131,072-ray stream (64 x 2048 at 10 Hz, synthetic street, ground-truth
// poses, moving points left out as a perfect scorer would): OctoMap insertion (occupied cells +
// free space carved by rays) and the free-space opinion (ground split, free-cell look-ups,
// clusters grown from the hits), at the default MapConfig.
//   build/bench/mapping_bench --benchmark_counters_tabular=true
#include <tbb/global_control.h>

#include <chrono>

#include "bench/bench_support.hpp"
#include "dynamics/ground_segmentation.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "mapping/free_space_vote.hpp"
#include "mapping/octomap_builder.hpp"
#include "mapping/point_cloud_map.hpp"
#include "odometry/deskew.hpp"

namespace cleanmap {
namespace {

struct StaticScan {
  Eigen::Matrix3Xf points;  // world frame, moving points removed
  Eigen::Matrix3Xf all;     // world frame, every point
  Eigen::Vector3d origin;
};

const std::vector<StaticScan>& os1_stream() {
  static const std::vector<StaticScan> scans = [] {
    LidarModel lidar;  // 64 x 2048
    const auto world = make_street_world(7);
    const auto sim = simulate_sequence(world, lidar, 30, 7);
    const auto& labels = sim.labels;
    const auto worlds = to_world(sim.scans);
    std::vector<StaticScan> out;
    for (std::size_t k = 0; k < worlds.size(); ++k) {
      const Scan& w = worlds[k];
      std::vector<Eigen::Index> keep;
      for (Eigen::Index i = 0; i < w.points.cols(); ++i) {
        const auto j = w.input_index.empty() ? static_cast<std::size_t>(i) : static_cast<std::size_t>(w.input_index[static_cast<std::size_t>(i)]);
        if ((labels[k][j] & 0xFFFF) != 251) keep.push_back(i);
      }
      out.push_back({w.points(Eigen::all, keep), w.points, w.pose->translation()});
    }
    return out;
  }();
  return scans;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void octomap_insert(benchmark::State& state) {
  tbb::global_control cores(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const auto& scans = os1_stream();
  std::vector<double> per_scan;
  std::size_t leaves = 0;
  for (auto _ : state) {
    OctoMapBuilder map(MapConfig{});
    for (const auto& s : scans) {
      const auto t = std::chrono::steady_clock::now();
      map.insert(s.points, s.origin);
      per_scan.push_back(seconds_since(t));
    }
    leaves = map.leaf_count();
  }
  state.counters["leaves"] = static_cast<double>(leaves);
  bench::report_latency(state, per_scan);
}

void free_space_opinion(benchmark::State& state) {
  tbb::global_control cores(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const auto& scans = os1_stream();
  std::vector<double> per_scan;
  std::size_t flagged = 0;
  for (auto _ : state) {
    OctoMapBuilder map(MapConfig{});
    for (const auto& s : scans) {
      const auto t = std::chrono::steady_clock::now();
      const auto objects = free_space_objects(
          s.all, [&](const Eigen::Matrix3Xf& sub) { return segment_ground(sub, GroundConfig{}); },
          [&](const Eigen::Matrix3Xf& sub) { return map.hits_in_free_space(sub); }, kFreeSpaceRule);
      per_scan.push_back(seconds_since(t));
      for (auto o : objects) flagged += o;
      map.insert(s.points, s.origin);
    }
  }
  state.counters["flagged_points"] = static_cast<double>(flagged);
  bench::report_latency(state, per_scan);
}

// The static map cloud (5 cm voxel filter, raw points kept) growing scan by scan.
void static_cloud(benchmark::State& state) {
  const auto& scans = os1_stream();
  std::vector<double> per_scan;
  std::size_t points = 0;
  for (auto _ : state) {
    PointCloudMap cloud(0.05);
    for (const auto& s : scans) {
      Scan scan;
      scan.points = s.points;
      const std::vector<std::uint8_t> keep(static_cast<std::size_t>(s.points.cols()), 1);
      const std::vector<float> score(keep.size(), 0.0f);
      const auto t = std::chrono::steady_clock::now();
      cloud.add(scan, keep, score, 0);
      per_scan.push_back(seconds_since(t));
    }
    points = cloud.size();
  }
  state.counters["map_points"] = static_cast<double>(points);
  bench::report_latency(state, per_scan);
}

BENCHMARK(static_cloud)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(octomap_insert)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(free_space_opinion)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace cleanmap

BENCHMARK_MAIN();
