#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace cleanmap::app {

// Creates the output folder (and subfolders), failing with a clear message when it cannot.
void make_dirs(const std::filesystem::path& dir);

// Writes OUT/summary.json atomically (temporary file, then rename): a reader never sees half a
// summary, and "complete": true appears only once everything else is written.
void write_summary(const std::filesystem::path& out, nlohmann::json summary, bool complete,
                   const std::string& error = "");

}  // namespace cleanmap::app
