#include "io/yaml_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "io/error.hpp"

namespace cleanmap {

YAML::Node load_yaml_file(const std::filesystem::path& file, const std::string& missing) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, missing);
  // Opened here, so that a file that cannot be read says why (issue 45: an unreadable
  // camera.yaml was "not valid YAML": yaml-cpp's LoadFile calls any failed open "bad file").
  errno = 0;
  std::ifstream in(file);
  if (!in) fail(file, std::string("cannot be read (") + (errno ? std::strerror(errno) : "open failed") + ")");
  try {
    return YAML::Load(in);
  } catch (const YAML::Exception& e) {
    fail(file, std::string("is not valid YAML (") + e.what() + ")");
  }
}

}  // namespace cleanmap
