// The Python module `cleanmap` (issue 44): settings, log reading, the online mapper and whole
// runs, with numpy in and out and the GIL released while C++ works.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "io/error.hpp"
#include "io/sequence.hpp"
#include "pipeline/online_mapper.hpp"
#include "pipeline/output_claim.hpp"
#include "pipeline/pipeline.hpp"
#include "python/config_binding.hpp"
#include "python/numpy_views.hpp"

namespace cleanmap::python {
using namespace pybind11::literals;
namespace {

// One scan as read_log yields it.
struct PyScan {
  py::array_t<float> points;
  py::object times, pose, labels;
  double stamp = 0.0;
  std::string name;
};

// Iterates a log: the sequence `cleanmap run` would open with these input settings.
struct LogReader {
  Sequence seq;
  std::size_t next = 0;
};

PyScan to_python(LoadedScan loaded) {
  PyScan s;
  s.stamp = loaded.scan.stamp;
  s.name = loaded.scan.name;
  s.times = loaded.scan.has_time() ? py::object(take_vector(std::vector<float>(
                                         loaded.scan.time.data(), loaded.scan.time.data() + loaded.scan.time.size())))
                                   : py::object(py::none());
  if (loaded.scan.has_time()) s.times = s.times.attr("astype")("float64");
  s.pose = loaded.scan.pose ? py::object(pose_array(*loaded.scan.pose)) : py::object(py::none());
  s.labels = loaded.labels.empty() ? py::object(py::none()) : py::object(take_vector(std::move(loaded.labels)));
  s.points = take_points(std::move(loaded.scan.points));
  return s;
}

Eigen::Isometry3d pose_from(const py::object& pose) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) throw Error("pose: must be a 4 x 4 matrix");
  Eigen::Isometry3d p;
  const auto m = a.unchecked<2>();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) p.matrix()(r, c) = m(r, c);
  }
  return p;
}

Scan scan_from(const py::object& points, const py::object& times, const py::object& pose, const py::object& stamp) {
  const auto p = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!p || p.ndim() != 2 || p.shape(1) != 3) throw Error("points: must be an N x 3 array");
  Scan scan;
  // The mapper keeps each scan over its window: the one copy, into the scan it owns.
  scan.points = Eigen::Map<const Eigen::Matrix3Xf>(p.data(), 3, p.shape(0));
  if (!times.is_none()) {
    const auto t = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(times);
    if (!t || t.ndim() != 1 || t.shape(0) != p.shape(0)) throw Error("times: must hold one number per point");
    scan.time = Eigen::Map<const Eigen::VectorXd>(t.data(), t.shape(0)).cast<float>();
  }
  if (!pose.is_none()) scan.pose = pose_from(pose);
  scan.stamp = stamp.is_none() ? std::numeric_limits<double>::quiet_NaN() : stamp.cast<double>();
  return scan;
}

py::list results(std::vector<pipeline::MapperResult> rs) {
  py::list out;
  auto ns = py::module_::import("types").attr("SimpleNamespace");
  for (auto& r : rs) {
    out.append(ns("index"_a = r.index, "labels"_a = take_vector(std::move(r.labels)),
                  "scores"_a = take_vector(std::move(r.scores)), "pose"_a = pose_array(r.pose)));
  }
  return out;
}

pipeline::PipelineConfig settings_of(const py::object& cfg) {
  return cfg.is_none() ? pipeline::PipelineConfig{} : cfg.cast<const Config&>().settings;
}

py::dict run(const std::string& input, const std::string& out, const py::object& cfg_obj, bool online,
             py::kwargs options) {
  bool use_given_poses = false, overwrite = false, mos = false;
  std::string mos_sequence;
  py::dict overrides;
  for (const auto& [k, v] : options) {
    const auto key = k.cast<std::string>();
    if (key == "use_given_poses") use_given_poses = v.cast<bool>();
    else if (key == "overwrite") overwrite = v.cast<bool>();
    else if (key == "mos_predictions") mos = v.cast<bool>();
    else if (key == "mos_sequence") mos_sequence = v.cast<std::string>();
    else overrides[k] = v;
  }
  const auto base = settings_of(cfg_obj);
  const auto cfg = overrides.empty() ? base : config_from({}, &base, overrides).settings;
  pipeline::PipelineOptions opt;
  opt.input = input;
  opt.out = out;
  opt.odometry = !(use_given_poses || !cfg.input.poses.empty());
  opt.mapping = true;
  opt.offline = !online;
  opt.command = "run";
  opt.mos_predictions = mos;
  opt.mos_sequence = mos_sequence;
  {
    py::gil_scoped_release free;
    pipeline::run_guarded({opt.out, "run", {opt.input, cfg.input.poses, cfg.input.times, cfg.input.camera}, overwrite},
                          [&] { pipeline::run_pipeline(opt, cfg, {}); }, /*handle_signals=*/false);
  }
  std::ifstream f(opt.out / "summary.json");
  std::stringstream text;
  text << f.rdbuf();
  return py::module_::import("json").attr("loads")(text.str());
}

// Errors keep the command line's message; a file that cannot be read or written is an OSError.
void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const Error& e) {
    const std::string m = e.what();
    for (const char* os : {"no such", "No such", "cannot create", "cannot open", "cannot write", "Permission denied",
                           "No space", "not a folder", "does not exist"}) {
      if (m.find(os) != std::string::npos) {
        PyErr_SetString(PyExc_OSError, m.c_str());
        return;
      }
    }
    PyErr_SetString(PyExc_ValueError, m.c_str());
  }
}

}  // namespace

PYBIND11_MODULE(cleanmap, m) {
  m.doc() = "cleanmap: clean static maps from lidar and depth logs (dynamic points removed)";
  py::register_exception_translator(&translate);
  bind_config(m);

  py::class_<PyScan>(m, "Scan", "One scan: points (N x 3 float32), times (N float64 or None), pose (4 x 4 or None), "
                                "stamp (s), labels (N uint32 or None), name")
      .def_readonly("points", &PyScan::points)
      .def_readonly("times", &PyScan::times)
      .def_readonly("pose", &PyScan::pose)
      .def_readonly("labels", &PyScan::labels)
      .def_readonly("stamp", &PyScan::stamp)
      .def_readonly("name", &PyScan::name);

  py::class_<LogReader>(m, "LogReader")
      .def("__len__", [](const LogReader& r) { return r.seq.size(); })
      .def("__iter__", [](LogReader& r) -> LogReader& { return r; })
      .def("__next__", [](LogReader& r) {
        if (r.next >= r.seq.size()) throw py::stop_iteration();
        LoadedScan loaded;
        {
          py::gil_scoped_release free;
          loaded = load_scan(r.seq, r.next++);
        }
        return to_python(std::move(loaded));
      });

  m.def(
      "read_log",
      [](const std::string& path, py::kwargs input_options) {
        py::dict as_input;
        for (const auto& [k, v] : input_options) as_input[("input_" + k.cast<std::string>()).c_str()] = v;
        const auto cfg = config_from({}, nullptr, as_input).settings;
        py::gil_scoped_release free;
        return LogReader{open_sequence(path, pipeline::sequence_options(cfg.input))};
      },
      "path"_a, "The scans of any log `cleanmap run` reads; options are the preset's input keys (poses=..., rate_hz=...)");

  py::class_<pipeline::OnlineMapper>(m, "OnlineMapper",
                                     "`cleanmap run --online`, one pushed scan at a time: results come back once final")
      .def(py::init([](const py::object& cfg) { return std::make_unique<pipeline::OnlineMapper>(settings_of(cfg)); }),
           "cfg"_a = py::none())
      .def(
          "push",
          [](pipeline::OnlineMapper& mapper, const py::object& points, const py::object& times, const py::object& pose,
             const py::object& stamp) {
            Scan scan = scan_from(points, times, pose, stamp);
            std::vector<pipeline::MapperResult> out;
            {
              py::gil_scoped_release free;
              out = mapper.push(std::move(scan));
            }
            return results(std::move(out));
          },
          "points"_a, "times"_a = py::none(), "pose"_a = py::none(), "stamp"_a = py::none())
      .def("finish",
           [](pipeline::OnlineMapper& mapper) {
             std::vector<pipeline::MapperResult> out;
             {
               py::gil_scoped_release free;
               out = mapper.finish();
             }
             return results(std::move(out));
           })
      .def("static_points", [](const pipeline::OnlineMapper& mapper) { return take_points(mapper.static_points()); },
           "The map's static points (N x 3 float32), relative to map_origin")
      .def_property_readonly(
          "map_origin",
          [](const pipeline::OnlineMapper& mapper) {
            const Eigen::Vector3d o = mapper.map_origin();
            return py::array_t<double>(3, o.data());
          },
          "The map's local origin in the pushed poses' frame (the first pose rounded to 1 km)");

  m.def("run", &run, "input"_a, "out"_a, "cfg"_a = py::none(), "online"_a = false,
        "What `cleanmap run` does; returns summary.json as a dict");
  m.attr("__version__") = "0.1.0";
}

}  // namespace cleanmap::python
