// Odometry time per scan on the real KITTI HDL-64 scans (../shared/data/kitti00, ~124k points,
// the 10 scans run again and again) and on the campus walk (balm_campus), and drift on the
// synthetic street against ground truth; point-to-plane (Ceres) against the plain
// point-to-point ICP baseline in the same run.
//   build/bench/odometry_bench --benchmark_counters_tabular=true
#include <tbb/global_control.h>

#include "bench/bench_support.hpp"
#include "io/sequence.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "odometry/lidar_odometry.hpp"

namespace cleanmap {
namespace {

// Time per scan of `cfg` on a real sequence in ../shared/data (all scans loaded first, the first
// scan of each pass left out: it only starts the map).
void sequence_time(benchmark::State& state, const char* folder, const OdometryConfig& cfg,
                   const char* method) {
  tbb::global_control cores(tbb::global_control::max_allowed_parallelism, 2);
  const auto seq = open_sequence(std::filesystem::path(CLEANMAP_SHARED_DATA) / folder);
  std::vector<Scan> scans;
  for (std::size_t i = 0; i < seq.size(); ++i) scans.push_back(load_scan(seq, i).scan);
  std::vector<double> per_scan;
  for (auto _ : state) {
    LidarOdometry odom(cfg);
    odom.method = method;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const auto step = odom.register_scan(scans[i]);
      if (i > 0) per_scan.push_back(step.seconds);
    }
  }
  bench::report_latency(state, per_scan);
}

void kitti_time(benchmark::State& state, const char* method) {
  OdometryConfig cfg;
  cfg.vertical_correction_deg = 0.205;
  sequence_time(state, "kitti00", cfg, method);
}

// The campus walk (balm_campus: 40 scans 0.5 s apart, ~75k points), default settings as a new
// user runs it.
void balm_time(benchmark::State& state) { sequence_time(state, "balm_campus", OdometryConfig{}, "point_to_plane"); }

void synthetic_drift(benchmark::State& state, const char* method) {
  tbb::global_control cores(tbb::global_control::max_allowed_parallelism, 2);
  LidarModel lidar;
  lidar.columns = 1024;
  const auto world = make_street_world(2);
  std::vector<Scan> scans;
  for (std::size_t i = 0; i < 60; ++i) scans.push_back(simulate_scan(world, lidar, i, 2).scan);
  double error = 0, distance = 0;
  for (auto _ : state) {
    LidarOdometry odom(OdometryConfig{});
    odom.method = method;
    Eigen::Isometry3d first;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const auto step = odom.register_scan(scans[i]);
      const auto truth = sensor_pose(world, scans[i].stamp + step.reference_offset);
      if (i == 0) first = truth;
      error = ((first.inverse() * truth).translation() - step.pose.translation()).norm();
      distance = (first.inverse() * truth).translation().norm();
    }
  }
  state.counters["final_error_m"] = error;
  state.counters["drift_percent"] = 100.0 * error / distance;
}

BENCHMARK_CAPTURE(kitti_time, point_to_plane, "point_to_plane")->Unit(benchmark::kSecond)->Iterations(5);
BENCHMARK_CAPTURE(kitti_time, point_to_point, "point_to_point")->Unit(benchmark::kSecond)->Iterations(5);
BENCHMARK(balm_time)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK_CAPTURE(synthetic_drift, point_to_plane, "point_to_plane")->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(synthetic_drift, point_to_point, "point_to_point")->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace cleanmap

BENCHMARK_MAIN();
