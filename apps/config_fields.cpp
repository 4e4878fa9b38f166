#include "apps/config_fields.hpp"

namespace cleanmap::app {

// Every section any command reads; a preset may carry all of them.
static const char* const kAllSections[] = {"input", "synthetic", "scorer", "odometry", "mapping"};

YAML::Node load_preset(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) fail(file, "no such config file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    fail(file, std::string("invalid YAML: ") + e.what());
  }
  if (root.IsNull()) return YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) fail(file, "top level must be a map of sections");
  for (const auto& kv : root) {
    const auto name = kv.first.as<std::string>();
    bool ok = false;
    for (const char* s : kAllSections) ok = ok || name == s;
    if (!ok) fail(file, "unknown section '" + name + "'");
  }
  return root;
}

}  // namespace cleanmap::app
