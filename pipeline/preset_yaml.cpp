#include "pipeline/preset_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <fstream>

#include "io/close_checked.hpp"

namespace cleanmap::pipeline {
namespace {

// Shortest text that reads back as the same double (0.3, not 0.29999999999999999).
std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".en") == std::string::npos) s += ".0";  // stays a float in YAML
  return s;
}

void emit(YAML::Emitter& out, const nlohmann::json& v) {
  if (v.is_boolean()) {
    out << v.get<bool>();
  } else if (v.is_number_integer() || v.is_number_unsigned()) {
    out << v.dump();
  } else if (v.is_number_float()) {
    out << shortest(v.get<double>());
  } else if (v.is_string()) {
    out << YAML::DoubleQuoted << v.get<std::string>();
  } else if (v.is_array()) {
    out << YAML::Flow << YAML::BeginSeq;
    for (const auto& e : v) emit(out, e);
    out << YAML::EndSeq;
  }
}

void section(YAML::Emitter& out, const char* name, const nlohmann::json& fields) {
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  for (const auto& [key, value] : fields.items()) {
    out << YAML::Key << key << YAML::Value;
    emit(out, value);
  }
  out << YAML::EndMap;
}

}  // namespace

std::string preset_yaml(const PipelineConfig& c, int sections) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  section(out, "input", to_json(c.input, input_fields()));
  if (sections & kOdometry) section(out, "odometry", to_json(c.odometry, odometry_fields()));
  if (sections & kScorer) section(out, "scorer", to_json(c.scorer, scorer_fields()));
  if (sections & kMapping) section(out, "mapping", to_json(c.mapping, mapping_fields()));
  out << YAML::EndMap;
  return std::string("# cleanmap preset: the effective settings (cleanmap config; --config reads it back)\n") +
         out.c_str() + "\n";
}

void write_preset(const std::filesystem::path& out, const PipelineConfig& config, int sections) {
  std::ofstream f(out / "config.yaml");
  f << preset_yaml(config, sections);
  close_checked(f, out / "config.yaml");
}

}  // namespace cleanmap::pipeline
