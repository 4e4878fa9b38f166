// YAML presets: every section of every command, each value checked against its field's range,
// then the modules' own validation, as `run` does it.
#include "apps/preset_options.hpp"
#include "odometry/lidar_odometry.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".yaml");
  cleanmap::fuzz::expect_clean([&] {
    CLI::App app;
    cleanmap::app::PresetOptions options;
    options.add_to(app, cleanmap::app::PresetOptions::kOdometry | cleanmap::app::PresetOptions::kScorer |
                            cleanmap::app::PresetOptions::kMapping);
    app.parse(std::vector<std::string>{});
    const auto cfg = options.resolve(app, file);
    cleanmap::validate(cfg.odometry);
    cleanmap::validate(cfg.scorer);
    cleanmap::validate(cfg.mapping.map);
    cleanmap::validate(cfg.mapping.visibility);
  });
  return 0;
}
