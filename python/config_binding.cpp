#include "python/config_binding.hpp"

#include <yaml-cpp/yaml.h>

#include <array>

#include "io/error.hpp"
#include "pipeline/config_fields.hpp"
#include "pipeline/preset_yaml.hpp"

namespace cleanmap::python {
namespace {

using pipeline::kMapping;
using pipeline::kOdometry;
using pipeline::kScorer;
constexpr int kAll = kOdometry | kScorer | kMapping;
constexpr std::array<const char*, 4> kSections{"input", "odometry", "scorer", "mapping"};

// A Python value as the YAML a preset would hold (yaml-cpp then reads it as the field's type).
YAML::Node to_yaml(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return YAML::Node(v.cast<bool>());
  if (py::isinstance<py::int_>(v)) return YAML::Node(v.cast<long long>());
  if (py::isinstance<py::float_>(v)) return YAML::Node(v.cast<double>());
  if (py::isinstance<py::str>(v)) return YAML::Node(v.cast<std::string>());
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& e : v) seq.push_back(to_yaml(e));
    return seq;
  }
  throw Error("a setting's value must be a bool, number, string or list, not " +
              std::string(py::str(py::type::of(v))));
}

// Which sections hold `key` (the field tables are the presets' own).
std::vector<std::string> sections_with(const std::string& key) {
  std::vector<std::string> found;
  auto look = [&](const char* section, const auto& fields) {
    std::apply([&](const auto&... f) { ((key == f.name ? found.push_back(section) : void()), ...); }, fields);
  };
  look("input", pipeline::input_fields());
  look("odometry", pipeline::odometry_fields());
  look("scorer", pipeline::scorer_fields());
  look("mapping", pipeline::mapping_fields());
  return found;
}

void set_override(YAML::Node& root, const std::string& key, const py::handle& value) {
  for (const char* s : kSections) {
    if (key == s) {
      if (!py::isinstance<py::dict>(value)) throw Error("override '" + key + "': a section takes a dict of its keys");
      for (const auto& [k, v] : value.cast<py::dict>()) root[s][k.cast<std::string>()] = to_yaml(v);
      return;
    }
  }
  for (const char* s : kSections) {
    const std::string prefix = std::string(s) + "_";
    if (key.rfind(prefix, 0) == 0 && !sections_with(key.substr(prefix.size())).empty()) {
      root[s][key.substr(prefix.size())] = to_yaml(value);
      return;
    }
  }
  const auto holders = sections_with(key);
  if (holders.size() == 1) {
    root[holders[0]][key] = to_yaml(value);
    return;
  }
  if (holders.empty()) throw Error("unknown setting '" + key + "' (preset keys, e.g. scorer_threshold=0.3)");
  throw Error("setting '" + key + "' is in more than one section: name it as " + holders[0] + "_" + key);
}

}  // namespace

Config config_from(const std::filesystem::path& path, const pipeline::PipelineConfig* base,
                   const py::dict& overrides) {
  YAML::Node root = base ? YAML::Load(pipeline::preset_yaml(*base, kAll))
                         : path.empty() ? YAML::Node(YAML::NodeType::Map) : pipeline::load_preset(path);
  for (const auto& [k, v] : overrides) set_override(root, k.cast<std::string>(), v);
  const std::filesystem::path named = path.empty() ? std::filesystem::path("overrides") : path;
  return {pipeline::config_from_preset(root, named, kAll)};
}

std::string config_yaml(const Config& c) { return pipeline::preset_yaml(c.settings, kAll); }

void bind_config(py::module_& m) {
  py::class_<Config>(m, "Config", "Every setting of a run: the preset sections input, odometry, scorer, mapping")
      .def(py::init([] { return Config{}; }))
      .def_static(
          "from_preset",
          [](py::object path, py::kwargs overrides) {
            const std::filesystem::path p = path.is_none() ? std::filesystem::path() : std::filesystem::path(py::str(path).cast<std::string>());
            return config_from(p, nullptr, overrides);
          },
          py::arg("path") = py::none(),
          "A preset file (None: the defaults) with overrides by preset key: scorer_threshold=0.3, "
          "scorer={'threshold': 0.3}, or a key only one section has")
      .def("with_overrides", [](const Config& c, py::kwargs overrides) { return config_from({}, &c.settings, overrides); },
           "A copy with these overrides on top")
      .def("to_yaml", &config_yaml, "The preset `cleanmap config` prints (--config reads it back)")
      .def("to_dict",
           [](const Config& c) {
             const auto j = nlohmann::json{{"input", pipeline::to_json(c.settings.input, pipeline::input_fields())},
                                           {"odometry", pipeline::to_json(c.settings.odometry, pipeline::odometry_fields())},
                                           {"scorer", pipeline::to_json(c.settings.scorer, pipeline::scorer_fields())},
                                           {"mapping", pipeline::to_json(c.settings.mapping, pipeline::mapping_fields())}};
             return py::module_::import("json").attr("loads")(j.dump());
           })
      .def("__repr__", [](const Config& c) { return "cleanmap.Config(\n" + config_yaml(c) + ")"; });
}

}  // namespace cleanmap::python
