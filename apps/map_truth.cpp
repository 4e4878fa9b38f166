#include "apps/map_truth.hpp"

#include <string>

#include "apps/cli_fields.hpp"
#include "io/cloud_file.hpp"
#include "io/error.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;

MapTruth read_map_truth(const std::filesystem::path& file) {
  MapTruth t;
  t.cloud = read_cloud(file);
  if (!t.cloud.has_intensity()) fail(file, "needs an intensity field (0 = static, 1 = dynamic)");
  t.dynamic.resize(t.cloud.size());
  for (std::size_t i = 0; i < t.dynamic.size(); ++i) {
    const float v = t.cloud.intensity[static_cast<Eigen::Index>(i)];
    if (v != 0.0f && v != 1.0f) {
      fail(file, "point " + std::to_string(i) + " has intensity " + format_number(v) +
                     ": ground truth must be 0 (static) or 1 (dynamic)");
    }
    t.dynamic[i] = v == 1.0f;
  }
  return t;
}

}  // namespace cleanmap::app
