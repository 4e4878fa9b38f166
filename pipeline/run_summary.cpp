#include "pipeline/run_summary.hpp"

#include <ceres/version.h>
#include <tbb/version.h>

#include <Eigen/Core>
#include <string>

#include "pipeline/output_dir.hpp"

namespace cleanmap::pipeline {

nlohmann::json metrics_json(const MovingConfusion& c) {
  return {{"iou", json_number(c.iou())}, {"precision", json_number(c.precision())},
          {"recall", json_number(c.recall())},
          {"tp", c.tp}, {"fp", c.fp}, {"fn", c.fn}, {"tn", c.tn}};
}

nlohmann::json library_versions() {
  return {{"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
                        "." + std::to_string(EIGEN_MINOR_VERSION)},
          {"octomap", CLEANMAP_OCTOMAP_VERSION},
          {"pcl", CLEANMAP_PCL_VERSION},
          {"ceres", CERES_VERSION_STRING},
          {"tbb", TBB_VERSION_STRING},
          {"cleanmap", "0.1.0"}};
}

}  // namespace cleanmap::pipeline
