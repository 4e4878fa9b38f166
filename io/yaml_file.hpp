#pragma once

#include <filesystem>
#include <string>
#include <yaml-cpp/yaml.h>

namespace cleanmap {

// Parses a YAML file, failing with one line that names it: `missing` says what the file should
// have been when there is none ("no such camera file (...)"), a parse error gives yaml-cpp's
// line and column. Presets, camera files and ROS 2 bag metadata all load through here.
YAML::Node load_yaml_file(const std::filesystem::path& file, const std::string& missing);

}  // namespace cleanmap
