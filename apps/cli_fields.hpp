#pragma once

// The command-line side of the config tables (pipeline/config_fields.hpp): one option per
// field, and command-line-over-preset precedence.

#include <CLI/CLI.hpp>

#include "pipeline/config_fields.hpp"

namespace cleanmap::app {
using pipeline::Range;
using pipeline::check_value;
using pipeline::option_name;

// A command-line check for a plain numeric option: a finite number in `r` (CLI11's own
// PositiveNumber lets NaN through).
CLI::Validator number_in(const Range& r);

// A value that is there: an empty string is no number.
inline const CLI::Validator kNotEmpty(
    [](std::string& text) { return text.empty() ? std::string("an empty value is not a number") : std::string(); }, "");

// One option per field, its built-in default and (numbers) the values it takes shown in
// --help; a bool is a flag with a --no- form (--free-space / --no-free-space;
// --free-space=false works too).
template <typename Config, typename Fields>
void add_options(CLI::App& app, Config& target, const Fields& fields) {
  auto one = [&](const auto& f) {
    auto& value = f.get(target);
    if constexpr (std::is_same_v<std::remove_reference_t<decltype(value)>, bool>) {
      const std::string name = option_name(f.name);
      app.add_flag(name + ",!--no-" + name.substr(2), value,
                   std::string(f.help) + (value ? " [default: on]" : " [default: off]"));
    } else {
      using T = std::remove_reference_t<decltype(value)>;
      std::string help = f.help;
      if constexpr (std::is_arithmetic_v<T>) help += "; " + pipeline::describe(pipeline::range_of<T>(f.range));
      auto* option = app.add_option(option_name(f.name), value, help)->capture_default_str();
      // CLI11 reads an empty string as 0 (issue 45: `--radius ''` ran with radius 0).
      if constexpr (std::is_arithmetic_v<T>) option->check(kNotEmpty);
    }
  };
  std::apply([&](const auto&... f) { (one(f), ...); }, fields);
}

// A command-line value that passed its field's check (else an error naming the option).
template <typename F, typename T>
const T& checked(const F& f, const T& value) {
  const std::string problem = check_value(value, f.range);
  if (!problem.empty()) throw Error(option_name(f.name) + ": " + problem);
  return value;
}

// Copies every field whose option was given on the command line from `cli` into `config`
// (each checked against its range).
template <typename Config, typename Fields>
void override_from_cli(const CLI::App& app, Config& config, Config& cli, const Fields& fields) {
  std::apply(
      [&](const auto&... f) {
        ((app.get_option(option_name(f.name))->count() > 0 ? void(f.get(config) = checked(f, f.get(cli)))
                                                           : void()),
         ...);
      },
      fields);
}

// --out and --overwrite on a command.
void add_output_options(CLI::App& cmd, std::filesystem::path& out, bool& overwrite, const std::string& help);

}  // namespace cleanmap::app
