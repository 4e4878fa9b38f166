#pragma once

#include <filesystem>

namespace cleanmap::app {

// A data file of cleanmap's (the report's script and viewer, the presets): beside an installed
// binary (PREFIX/bin/cleanmap -> PREFIX/share/cleanmap/NAME), else `in_build`, where the build
// tree it came from has it.
std::filesystem::path installed_file(const std::filesystem::path& name, const std::filesystem::path& in_build);

}  // namespace cleanmap::app
