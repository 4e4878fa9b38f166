#pragma once

// The preset sections as command-line options: registered on a command, then resolved
// (defaults <- preset section <- command line).

#include <CLI/CLI.hpp>
#include <filesystem>
#include <vector>

#include "apps/cli_fields.hpp"
#include "pipeline/settings.hpp"

namespace cleanmap::app {
using pipeline::InputSettings;
using pipeline::MappingSettings;
using pipeline::PipelineConfig;

// Defaults <- preset section <- options given on the command line.
template <typename Config, typename Fields>
Config resolve(const CLI::App& cmd, const YAML::Node& preset, const std::filesystem::path& file,
               const char* section, Config defaults, Config cli, const Fields& fields) {
  if (preset && preset[section]) pipeline::apply_yaml(preset[section], defaults, fields, file, section);
  override_from_cli(cmd, defaults, cli, fields);
  return defaults;
}

// The preset sections a command takes: registered as command-line options, then resolved
// (defaults <- preset section <- command line) in one place. `input` always; the others as
// the command asks. Sections a command does not take keep their defaults.
struct PresetOptions {
  static constexpr int kOdometry = pipeline::kOdometry, kScorer = pipeline::kScorer, kMapping = pipeline::kMapping;
  PipelineConfig cli;  // the options' targets (only those given on the command line count)
  int sections = 0;

  void add_to(CLI::App& cmd, int with) {
    sections = with;
    add_options(cmd, cli.input, pipeline::input_fields());
    if (with & kOdometry) add_options(cmd, cli.odometry, pipeline::odometry_fields());
    if (with & kScorer) add_options(cmd, cli.scorer, pipeline::scorer_fields());
    if (with & kMapping) add_options(cmd, cli.mapping, pipeline::mapping_fields());
  }

  // What a command reads (never written, never under --out): the log, the preset, and the pose,
  // time and camera files given on the command line.
  std::vector<std::filesystem::path> input_files(const std::filesystem::path& input,
                                                 const std::filesystem::path& preset) const {
    return {input, preset, cli.input.poses, cli.input.times, cli.input.camera};
  }

  PipelineConfig resolve(const CLI::App& cmd, const std::filesystem::path& preset_file) const {
    const auto preset = pipeline::load_optional_preset(preset_file);
    PipelineConfig c;
    c.input = app::resolve(cmd, preset, preset_file, "input", InputSettings{}, cli.input, pipeline::input_fields());
    if (sections & kOdometry) {
      c.odometry = app::resolve(cmd, preset, preset_file, "odometry", OdometryConfig{}, cli.odometry, pipeline::odometry_fields());
    }
    if (sections & kScorer) {
      c.scorer = app::resolve(cmd, preset, preset_file, "scorer", ScorerConfig{}, cli.scorer, pipeline::scorer_fields());
    }
    if (sections & kMapping) {
      c.mapping = app::resolve(cmd, preset, preset_file, "mapping", MappingSettings{}, cli.mapping, pipeline::mapping_fields());
    }
    return c;
  }
};

}  // namespace cleanmap::app
