#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>

#include "apps/commands.hpp"
#include "apps/installed_file.hpp"
#include "pipeline/output_dir.hpp"
#include "evaluation/trajectory_metrics.hpp"
#include "io/close_checked.hpp"
#include "io/cloud_file.hpp"
#include "io/error.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;
namespace fs = std::filesystem;
namespace {

// Every k-th point's x, y, z (flat), at most about `limit` of them: enough for a top view and
// for the 3D view to stay a few MB.
nlohmann::json sample_cloud(const fs::path& file, std::size_t limit) {
  std::vector<double> xyz;
  if (fs::exists(file)) {
    const Scan cloud = read_cloud(file);
    const std::size_t step = std::max<std::size_t>(1, (cloud.size() + limit - 1) / limit);
    for (std::size_t i = 0; i < cloud.size(); i += step) {
      for (int k = 0; k < 3; ++k) xyz.push_back(cloud.points(k, static_cast<Eigen::Index>(i)));
    }
  }
  return {{"xyz", xyz}};
}

void add_trajectory(const fs::path& out, fs::path ref, const nlohmann::json& summary, nlohmann::json& d);

nlohmann::json read_summary(const fs::path& out) {
  const fs::path file = out / "summary.json";
  if (!fs::exists(file)) fail(out, "has no summary.json: not a cleanmap output folder");
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(std::ifstream(file));
  } catch (const nlohmann::json::exception& e) {
    fail(file, std::string("is not valid JSON (") + e.what() + ")");
  }
  if (!summary.is_object() || !summary.contains("command")) fail(file, "is not a cleanmap summary (no \"command\")");
  return summary;
}

void make_report(const fs::path& out, fs::path ref, const std::string& python, const fs::path& script,
                 const fs::path& viewer) {
  const auto summary = read_summary(out);
  make_dirs(out / "report");
  nlohmann::json d;
  d["summary"] = summary;
  d["per_scan"] = summary.value("per_scan", nlohmann::json::array());
  // A run that stopped says so at the top of the page; what it left is drawn where readable.
  const bool complete = summary.value("complete", false);
  d["complete"] = complete;
  d["error"] = summary.value("error", complete ? "" : "no reason recorded (still running, or killed)");
  d["problems"] = nlohmann::json::array();
  auto guarded = [&](const char* what, const std::function<void()>& part) {
    try {
      part();
    } catch (const Error& e) {
      if (complete) throw;
      d["problems"].push_back(std::string(what) + ": " + e.what());
    }
  };
  if (!complete) std::fprintf(stderr, "cleanmap: warning: %s describes an incomplete run: %s\n", out.c_str(),
                              d["error"].get<std::string>().c_str());
  const bool is_map = fs::exists(out / "map_static.pcd");
  guarded("static cloud", [&] { d["static_cloud"] = sample_cloud(out / (is_map ? "map_static.pcd" : "static.pcd"), 150000); });
  guarded("dynamic cloud", [&] { d["dynamic_cloud"] = sample_cloud(out / (is_map ? "map_dynamic.pcd" : "dynamic.pcd"), 50000); });
  guarded("trajectory", [&] { add_trajectory(out, ref, summary, d); });
  if (!fs::exists(script)) fail(script, "report script not found (give --script)");
  // The numbers reach the script through a file that lives only as long as this call (it was
  // left behind as a 7.9 MB report/data.json).
  const RemovedAtExit data(out / "report" / ".data.json");
  {
    std::ofstream f(data.path);
    if (!f) fail(data.path, "cannot create file");
    f << d.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    close_checked(f, data.path);
  }
  std::string cmd = "'" + python + "' '" + script.string() + "' '" + out.string() + "' '" + data.path.string() + "'";
  if (!viewer.empty()) cmd += " '" + viewer.string() + "'";
  if (std::system(cmd.c_str()) != 0) {
    fail(script, "failed (it needs Debian's python3-matplotlib: apt-get install python3-matplotlib)");
  }
  std::printf("report: %s (plots in %s)\n", (out / "report.html").c_str(), (out / "report").c_str());
}

void add_trajectory(const fs::path& out, fs::path ref, const nlohmann::json& summary, nlohmann::json& d) {
  if (fs::exists(out / "poses_kitti.txt")) {
    std::vector<Eigen::Isometry3d> est;
    for (const auto& p : read_poses(out / "poses_kitti.txt")) est.push_back(p.pose);
    if (ref.empty() && summary.contains("input")) {
      const fs::path guess = fs::path(summary["input"].get<std::string>()) / "poses.txt";
      if (fs::exists(guess)) ref = guess;
    }
    std::vector<Eigen::Isometry3d> r;
    if (!ref.empty()) {
      for (const auto& p : read_poses(ref)) r.push_back(p.pose);
      if (r.size() != est.size()) fail(ref, "has " + std::to_string(r.size()) + " poses for " + std::to_string(est.size()) + " estimated");
    }
    if (!r.empty()) {
      const auto ape = absolute_pose_error(r, est, Alignment::kSE3);
      const auto rpe = relative_pose_error(r, est, 1);
      const auto kitti = kitti_errors(r, est);
      nlohmann::json est_xy = nlohmann::json::array(), ref_xy = nlohmann::json::array(), errors = nlohmann::json::array(),
                     dist = nlohmann::json::array();
      double travelled = 0;
      for (std::size_t i = 0; i < est.size(); ++i) {
        const Eigen::Vector3d a = (ape.alignment * est[i].translation().homogeneous()).head<3>();
        est_xy.push_back({a.x(), a.y(), a.z()});
        ref_xy.push_back({r[i].translation().x(), r[i].translation().y(), r[i].translation().z()});
        if (i > 0) travelled += (r[i].translation() - r[i - 1].translation()).norm();
        errors.push_back((a - r[i].translation()).norm());
        dist.push_back(travelled);
      }
      d["estimate"] = est_xy;
      d["reference"] = ref_xy;
      d["ape_per_pose"] = errors;
      d["distance"] = dist;
      auto stats = [](const ErrorStats& s) { return nlohmann::json{{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}}; };
      d["ape"] = stats(ape.translation);
      d["rpe"] = stats(rpe.translation);
      d["kitti"] = kitti_json(kitti);
    } else {
      nlohmann::json est_xy = nlohmann::json::array();
      for (const auto& p : est) est_xy.push_back({p.translation().x(), p.translation().y(), p.translation().z()});
      d["estimate"] = est_xy;
    }
  }
}

}  // namespace

void register_report(CLI::App& app) {
  struct Args {
    fs::path out, ref, script = installed_file("report.py", CLEANMAP_REPORT_SCRIPT);
    // The bundled three.js view; without it (npm never ran) the page says why it has none.
    fs::path viewer = installed_file("viewer.js", CLEANMAP_VIEWER_JS);
    std::string python = "/usr/bin/python3";  // Debian's, which has python3-matplotlib
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("report", "A self-contained HTML report (plots and tables) of an output folder");
  cmd->add_option("out", args->out, "Output folder of run, score or odometry")->required();
  cmd->add_option("--ref", args->ref, "Reference poses; default <input>/poses.txt when present");
  cmd->add_option("--python", args->python, "Python with matplotlib")->capture_default_str();
  cmd->add_option("--script", args->script, "The plotting script")->capture_default_str();
  cmd->add_option("--viewer", args->viewer, "The bundled 3D view (empty: none)")->capture_default_str();
  cmd->callback([args] {
    std::error_code ec;
    const fs::path viewer = fs::exists(args->viewer, ec) ? args->viewer : fs::path();
    make_report(args->out, args->ref, args->python, args->script, viewer);
  });
}

}  // namespace cleanmap::app
