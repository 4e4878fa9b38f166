#include "pipeline/config_fields.hpp"

#include <cstdio>

#include "io/yaml_file.hpp"

namespace cleanmap::pipeline {

// Every section any command reads; a preset may carry all of them.
static const char* const kAllSections[] = {"input", "synthetic", "scorer", "odometry", "mapping"};

std::string format_number(double v) {
  char buf[32];
  // Whole numbers in full (an int's 2147483647, not %g's 2.14748e+09), up to where a double
  // still holds every integer.
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15 && std::abs(v) >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
  } else {
    std::snprintf(buf, sizeof buf, "%g", v);
  }
  return buf;
}

std::string describe(const Range& r) {
  auto num = [](double v) { return format_number(v); };
  const bool lo = std::isfinite(r.lo), hi = std::isfinite(r.hi);
  if (lo && hi) return std::string("in ") + (r.lo_open ? "(" : "[") + num(r.lo) + ", " + num(r.hi) + "]";
  if (lo) return (r.lo_open ? "> " : ">= ") + num(r.lo);
  if (hi) return "<= " + num(r.hi);
  return "finite";
}

std::string key_name(const YAML::Node& key, const std::filesystem::path& file) {
  // A key that is a list or a map (`[a]: 1`, `{a: 1}: 2`) threw yaml-cpp's own BadConversion,
  // a message without the file (found by fuzz_preset).
  if (!key.IsScalar()) {
    fail(file, "line " + std::to_string(key.Mark().line + 1) + ": a key must be a plain name, not a list or a map");
  }
  return key.Scalar();
}

YAML::Node load_preset(const std::filesystem::path& file) {
  const YAML::Node root = load_yaml_file(file, "no such config file");
  if (root.IsNull()) return YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) fail(file, "top level must be a map of sections");
  for (const auto& kv : root) {
    const auto name = key_name(kv.first, file);
    bool ok = false;
    for (const char* s : kAllSections) ok = ok || name == s;
    if (!ok) fail(file, "unknown section '" + name + "'");
  }
  return root;
}

}  // namespace cleanmap::pipeline
