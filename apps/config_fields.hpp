#pragma once

// One table per config struct lists its settable fields; YAML loading, command-line options,
// command-line-over-YAML precedence and the JSON summary are all driven by that one table.

#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>

#include "io/error.hpp"

namespace cleanmap::app {

template <typename Get>
struct Field {
  const char* name;  // YAML key; the option is --name with '_' as '-'
  const char* help;
  Get get;           // config& -> member&
};

template <typename Get>
Field<Get> field(const char* name, const char* help, Get get) {
  return {name, help, get};
}

// Field of a config struct by member path, e.g. CLEANMAP_FIELD("beams", lidar.beams, "...").
#define CLEANMAP_FIELD(key, path, help) \
  ::cleanmap::app::field(key, help, [](auto& c) -> auto& { return c.path; })

inline std::string option_name(const char* key) {
  std::string s = std::string("--") + key;
  for (auto& ch : s) ch = ch == '_' ? '-' : ch;
  return s;
}

template <typename Config, typename Fields>
void add_options(CLI::App& app, Config& target, const Fields& fields) {
  std::apply([&](const auto&... f) { (app.add_option(option_name(f.name), f.get(target), f.help), ...); },
             fields);
}

// Sets `config` from a YAML map; any key not in the table is an error naming file and key.
template <typename Config, typename Fields>
void apply_yaml(const YAML::Node& map, Config& config, const Fields& fields,
                const std::filesystem::path& file, const std::string& section) {
  if (!map.IsMap()) fail(file, "section '" + section + "' must be a map of key: value");
  for (const auto& kv : map) {
    const auto key = kv.first.as<std::string>();
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
           }())
                           : void()),
           ...);
        },
        fields);
    if (!found) fail(file, "unknown key '" + section + "." + key + "'");
  }
}

// Copies every field whose option was given on the command line from `cli` into `config`.
template <typename Config, typename Fields>
void override_from_cli(const CLI::App& app, Config& config, Config& cli, const Fields& fields) {
  std::apply(
      [&](const auto&... f) {
        ((app.get_option(option_name(f.name))->count() > 0 ? void(f.get(config) = f.get(cli))
                                                           : void()),
         ...);
      },
      fields);
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

}  // namespace cleanmap::app
