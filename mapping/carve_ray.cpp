#include "mapping/carve_ray.hpp"

namespace cleanmap {

void carve_ray(const octomap::OcTree& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               bool include_first, CellSet& carved) {
  walk_ray(tree, from, to, include_first, carved, [](const CellSet::Key&, double, double) { return true; });
}

}  // namespace cleanmap
