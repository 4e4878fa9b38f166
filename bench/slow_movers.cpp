// Not a benchmark: the slow-mover limit (issue 47), measured, for the README. A pedestrian (a
// cylinder 0.3 m in radius, 1.75 m tall) walks toward, or across the view of, a 64-beam lidar
// (2048 columns, 10 Hz, 1 cm range noise) that stands or drives along a wall behind the walker.
// Each log goes through `run --online --use-given-poses` with a preset (the SemanticKITTI one
// by default) in pipeline::OnlineMapper, the same stages; the table gives the share of the
// walker's points labelled moving, and the static points labelled moving (false points).
//   build/bench/slow_movers [--ranges 10,20] [--speeds 0.1,0.2,...] [--seconds 1,3,5]
//                           [--sensor-speed 0] [--config PRESET] [--per-scan]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "io/label_file.hpp"
#include "pipeline/online_mapper.hpp"
#include "pipeline/config_fields.hpp"
#include "pipeline/settings.hpp"
#include "simulation/synthetic_lidar.hpp"

namespace {
using namespace cleanmap;

std::vector<double> numbers(const std::string& csv) {
  std::vector<double> out;
  std::stringstream s(csv);
  for (std::string item; std::getline(s, item, ',');) out.push_back(std::stod(item));
  return out;
}

struct Found {
  std::size_t moving = 0, found = 0, false_points = 0;
  std::vector<std::pair<std::size_t, std::size_t>> per_scan;  // found, moving, by scan
};

enum class Walk { kAcross, kToward };

// The walker at `range` halfway through the log, across the line of sight or toward the sensor;
// the sensor stands, or drives along the wall at `sensor_speed`.
Found walker(const pipeline::PipelineConfig& cfg, Walk walk, double range, double speed, double seconds,
             double sensor_speed) {
  SyntheticWorld w;
  w.speed = sensor_speed;
  w.sway_amplitude = 0.0;
  const double half = 0.5 * speed * seconds;
  const double wall = range + 4.0 + (walk == Walk::kToward ? half : 0.0);
  w.objects.push_back({SceneObject::Shape::kBox, {wall, 0.0}, {0, 0}, 0.0, {1.0, 200.0, 4.0}, 80.f, 1});
  const double along = 0.5 * sensor_speed * seconds;  // where the sensor is halfway through
  if (walk == Walk::kAcross) {
    w.objects.push_back({SceneObject::Shape::kCylinder, {range, along - half}, {0.0, speed}, 0.0, {0.3, 0, 1.75}, 40.f, 2});
  } else {
    w.objects.push_back({SceneObject::Shape::kCylinder, {range + half, along}, {-speed, 0.0}, 0.0, {0.3, 0, 1.75}, 40.f, 2});
  }
  LidarModel lidar;
  const auto scans = static_cast<std::size_t>(seconds * lidar.rate_hz + 0.5);
  pipeline::OnlineMapper mapper{cfg};
  Found f;
  std::vector<std::vector<std::uint32_t>> truth(scans);
  f.per_scan.resize(scans);
  const auto tally = [&](const std::vector<pipeline::MapperResult>& results) {
    for (const auto& r : results) {
      const auto& gt = truth[r.index];
      for (std::size_t i = 0; i < gt.size(); ++i) {
        const bool moving = is_moving_label(gt[i]), said = r.labels[i] == kLabelMoving;
        f.moving += moving;
        f.found += moving && said;
        f.false_points += !moving && said;
        f.per_scan[r.index].first += moving && said;
        f.per_scan[r.index].second += moving;
      }
    }
  };
  for (std::size_t k = 0; k < scans; ++k) {
    auto s = simulate_scan(w, lidar, k, 7);
    truth[k] = std::move(s.labels);
    tally(mapper.push(std::move(s.scan)));
  }
  tally(mapper.finish());
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The slowest walker `run --online` finds, by range and log length (issue 47)"};
  std::string ranges = "10,20", speeds = "0.1,0.2,0.3,0.5,0.8,1.2", seconds = "1,3,5";
  std::string preset = std::string(CLEANMAP_SOURCE_DIR) + "/config/kitti-hdl64.yaml";
  double sensor_speed = 0.0;
  bool per_scan = false;
  app.add_flag("--per-scan", per_scan, "Also print each scan's share found (the log's ends)");
  app.add_option("--sensor-speed", sensor_speed, "The sensor's speed along the wall, m/s (0: standing)");
  app.add_option("--config", preset, "Preset (default: the SemanticKITTI one, a 64-beam car lidar)");
  app.add_option("--ranges", ranges, "Walker's range from the sensor, m (comma-separated)");
  app.add_option("--speeds", speeds, "Walking speeds, m/s");
  app.add_option("--seconds", seconds, "Log lengths, s (10 scans per second)");
  CLI11_PARSE(app, argc, argv);
  const auto cfg = pipeline::config_from_preset(pipeline::load_preset(preset), preset,
                                                pipeline::kOdometry | pipeline::kScorer | pipeline::kMapping);
  std::printf("preset %s\n", preset.c_str());
  std::printf("%-7s %8s %8s %8s %10s %10s %12s\n", "walks", "range m", "log s", "speed", "found %", "points",
              "false pts");
  for (const Walk walk : {Walk::kToward, Walk::kAcross}) {
    for (const double r : numbers(ranges)) {
      for (const double t : numbers(seconds)) {
        for (const double v : numbers(speeds)) {
          const Found f = walker(cfg, walk, r, v, t, sensor_speed);
          const double share = f.moving ? 100.0 * static_cast<double>(f.found) / static_cast<double>(f.moving) : 0.0;
          std::printf("%-7s %8.0f %8.0f %8.2f %10.1f %10zu %12zu\n", walk == Walk::kToward ? "toward" : "across", r, t,
                      v, share, f.moving, f.false_points);
          if (per_scan) {
            std::printf("        per scan:");
            for (const auto& [found, moving] : f.per_scan) std::printf(" %zu/%zu", found, moving);
            std::printf("\n");
          }
          std::fflush(stdout);
        }
      }
    }
  }
}
