#pragma once

#include <string>

#include "pipeline/settings.hpp"

namespace cleanmap::pipeline {

// The settings as a YAML preset that --config reads back to the same values: one section per
// part the command uses (PresetOptions sections; "input" always), every field with its value.
std::string preset_yaml(const PipelineConfig& config, int sections);

// OUT/config.yaml: the preset a command ran with, so `--config OUT/config.yaml` repeats it.
void write_preset(const std::filesystem::path& out, const PipelineConfig& config, int sections);

}  // namespace cleanmap::pipeline
