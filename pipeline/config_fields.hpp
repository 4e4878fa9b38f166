#pragma once

// One table per config struct lists its settable fields; YAML loading, the JSON summary and
// (apps/cli_fields.hpp) the command-line options are all driven by that one table.

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "io/error.hpp"

namespace cleanmap::pipeline {

// The values a numeric setting may take (every floating-point one must be finite as well).
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  // lo itself excluded ("must be positive")
};
inline constexpr Range kAny{};
inline constexpr Range kPositive{0.0, std::numeric_limits<double>::infinity(), true};
inline constexpr Range kNonNegative{0.0, std::numeric_limits<double>::infinity(), false};
inline constexpr Range kShare{0.0, 1.0, false};
inline constexpr Range kAtLeastOne{1.0, std::numeric_limits<double>::infinity(), false};

template <typename Get>
struct Field {
  const char* name;  // YAML key; the option is --name with '_' as '-'
  const char* help;
  Get get;           // config& -> member&
  Range range;
};

template <typename Get>
Field<Get> field(const char* name, const char* help, Get get, Range range = kAny) {
  return {name, help, get, range};
}

// Field of a config struct by member path, e.g. CLEANMAP_FIELD("beams", lidar.beams, "...").
#define CLEANMAP_FIELD(key, path, help) \
  ::cleanmap::pipeline::field(key, help, [](auto& c) -> auto& { return c.path; })
// The same with the values it may take, e.g. CLEANMAP_FIELD_IN("radius", radius, kPositive, "...").
#define CLEANMAP_FIELD_IN(key, path, range, help) \
  ::cleanmap::pipeline::field(key, help, [](auto& c) -> auto& { return c.path; }, range)

std::string describe(const Range& r);

// The range a field of type T can take: its own, within what T holds (an int's "at least 1" is
// [1, 2147483647]; an unsigned one is never negative).
template <typename T>
Range range_of(Range r) {
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    r.lo = std::max(r.lo, static_cast<double>(std::numeric_limits<T>::lowest()));
    r.hi = std::min(r.hi, static_cast<double>(std::numeric_limits<T>::max()));
  }
  return r;
}
std::string key_name(const YAML::Node& key, const std::filesystem::path& file);  // a map's key, or an error
std::string format_number(double v);  // %g: 1, 0.5, 1e-09

// Empty when `value` may be set; else what is wrong ("must be a finite number", "must be > 0").
template <typename T>
std::string check_value(const T& value, const Range& r) {
  if constexpr (std::is_same_v<T, bool>) {
    return {};
  } else if constexpr (std::is_arithmetic_v<T>) {
    const double v = static_cast<double>(value);
    if (!std::isfinite(v)) return "must be a finite number";
    if (v < r.lo || (r.lo_open && v == r.lo) || v > r.hi) return "must be " + describe(r) + ", not " + format_number(v);
    return {};
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    for (double v : value) {
      if (!std::isfinite(v)) return "must hold finite numbers";
    }
    return {};
  } else {
    return {};
  }
}

inline std::string option_name(const char* key) {
  std::string s = std::string("--") + key;
  for (auto& ch : s) ch = ch == '_' ? '-' : ch;
  return s;
}

// Sets `config` from a YAML map; any key not in the table is an error naming file and key.
template <typename Config, typename Fields>
void apply_yaml(const YAML::Node& map, Config& config, const Fields& fields,
                const std::filesystem::path& file, const std::string& section) {
  if (!map.IsMap()) fail(file, "section '" + section + "' must be a map of key: value");
  for (const auto& kv : map) {
    const auto key = key_name(kv.first, file);
    bool found = false;
    std::apply(
        [&](const auto&... f) {
          ((key == f.name ? (found = true, [&] {
             using T = std::remove_reference_t<decltype(f.get(config))>;
             try {
               f.get(config) = kv.second.template as<T>();
             } catch (const YAML::Exception&) {
               fail(file, section + "." + key + ": cannot read '" + YAML::Dump(kv.second) +
                              "' as the expected type");
             }
             const std::string problem = check_value(f.get(config), f.range);
             if (!problem.empty()) fail(file, section + "." + key + ": " + problem);
           }())
                           : void()),
           ...);
        },
        fields);
    if (!found) fail(file, "unknown key '" + section + "." + key + "'");
  }
}

template <typename Config, typename Fields>
nlohmann::json to_json(const Config& config, const Fields& fields) {
  nlohmann::json j = nlohmann::json::object();
  std::apply([&](const auto&... f) { ((j[f.name] = f.get(config)), ...); }, fields);
  return j;
}

// Loads a preset file: returns its root map after checking that every top-level section is one
// that some command reads (sections of other commands are allowed, misspelt ones are not).
YAML::Node load_preset(const std::filesystem::path& file);

}  // namespace cleanmap::pipeline
