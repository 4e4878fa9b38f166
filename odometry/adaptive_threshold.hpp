#pragma once

#include <Eigen/Geometry>

namespace cleanmap {

// Correspondence distance from how far the constant-velocity prediction has been from the
// registered poses so far (KISS-ICP, Vizzo et al. 2023, Sec. III-C): the RMS of the model
// error 2 r_max sin(theta/2) + |t| over scans that moved at least `min_motion`.
struct AdaptiveThreshold {
  double initial = 2.0;
  double min_motion = 0.1;
  double max_range = 100.0;
  double sse = 0.0;
  int samples = 0;

  double value() const { return samples == 0 ? initial : std::sqrt(sse / samples); }
  void update(const Eigen::Isometry3d& prediction_error) {
    const double angle = Eigen::AngleAxisd(prediction_error.rotation()).angle();
    const double error = 2.0 * max_range * std::sin(angle / 2.0) + prediction_error.translation().norm();
    if (error > min_motion) {
      sse += error * error;
      ++samples;
    }
  }
};

}  // namespace cleanmap
