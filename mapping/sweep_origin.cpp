#include "mapping/sweep_origin.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cleanmap {

SweepOrigin sweep_origin(const std::vector<StampedPose>& poses, std::size_t i, double stamp) {
  if (i >= poses.size()) throw std::out_of_range("sweep_origin: no pose for scan " + std::to_string(i));
  SweepOrigin s;
  s.start = poses[i].pose.translation();
  const std::size_t a = i > 0 ? i - 1 : i, b = i + 1 < poses.size() ? i + 1 : i;
  const double dt = poses[b].stamp - poses[a].stamp;
  if (a == b || !std::isfinite(dt) || !(dt > 0)) return s;
  s.velocity = (poses[b].pose.translation() - poses[a].pose.translation()) / dt;
  const double back = poses[i].stamp - stamp;  // pose i's time after the scan's stamp
  if (std::isfinite(back)) s.start -= s.velocity * back;
  return s;
}

}  // namespace cleanmap
