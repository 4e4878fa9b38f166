#pragma once

#include <pybind11/pybind11.h>

#include <filesystem>
#include <string>

#include "pipeline/settings.hpp"

namespace cleanmap::python {
namespace py = pybind11;

// cleanmap.Config: every setting of a run (pipeline::PipelineConfig).
struct Config {
  pipeline::PipelineConfig settings;
};

// The preset at `path` (none: the defaults) with `overrides` on top: preset keys by section,
// as `scorer_threshold=0.3`, `scorer={"threshold": 0.3}` or, when only one section has it, a
// bare `threshold=0.3`. Checked as a preset file is (unknown keys, ranges, types).
Config config_from(const std::filesystem::path& path, const pipeline::PipelineConfig* base,
                   const py::dict& overrides);

// The preset `cleanmap config` prints for these settings.
std::string config_yaml(const Config& c);

void bind_config(py::module_& m);

}  // namespace cleanmap::python
