#include "io/yaml_file.hpp"

#include "io/error.hpp"

namespace cleanmap {

YAML::Node load_yaml_file(const std::filesystem::path& file, const std::string& missing) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, missing);
  try {
    return YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    fail(file, std::string("is not valid YAML (") + e.what() + ")");
  }
}

}  // namespace cleanmap
