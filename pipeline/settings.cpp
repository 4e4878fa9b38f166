#include "pipeline/settings.hpp"

namespace cleanmap::pipeline {
namespace {

template <typename Config, typename Fields>
Config from_section(const YAML::Node& preset, const std::filesystem::path& file, const char* section,
                    const Fields& fields) {
  Config c;
  if (preset && preset[section]) apply_yaml(preset[section], c, fields, file, section);
  return c;
}

}  // namespace

PipelineConfig config_from_preset(const YAML::Node& preset, const std::filesystem::path& file, int sections) {
  PipelineConfig c;
  c.input = from_section<InputSettings>(preset, file, "input", input_fields());
  if (sections & kOdometry) c.odometry = from_section<OdometryConfig>(preset, file, "odometry", odometry_fields());
  if (sections & kScorer) c.scorer = from_section<ScorerConfig>(preset, file, "scorer", scorer_fields());
  if (sections & kMapping) c.mapping = from_section<MappingSettings>(preset, file, "mapping", mapping_fields());
  return c;
}

}  // namespace cleanmap::pipeline
