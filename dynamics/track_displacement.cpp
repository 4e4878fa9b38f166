#include "dynamics/track_displacement.hpp"

#include <cmath>
#include <limits>

namespace cleanmap {

Shift register_shift(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to, float reach) {
  Shift s;
  if (from.cols() == 0 || to.cols() == 0) return s;
  const float reach_sq = reach * reach;
  Eigen::Index paired = 0;
  // 20 rounds: a shift of half the reach converges in 5-10 on the test shapes; the loop
  // stops once a round moves it by under a millimetre.
  for (int round = 0; round < 20; ++round) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    paired = 0;
    for (Eigen::Index i = 0; i < from.cols(); ++i) {
      const Eigen::Vector3f p = from.col(i) + s.by;
      float best = std::numeric_limits<float>::infinity();
      Eigen::Index at = 0;
      for (Eigen::Index j = 0; j < to.cols(); ++j) {
        const float d = (to.col(j) - p).squaredNorm();
        if (d < best) {
          best = d;
          at = j;
        }
      }
      if (best > reach_sq) continue;
      sum += to.col(at) - p;
      ++paired;
    }
    if (paired == 0) break;
    const Eigen::Vector3f step = sum / static_cast<float>(paired);
    s.by += step;
    if (step.norm() < 1e-3f) break;
  }
  s.overlap = static_cast<float>(paired) / static_cast<float>(from.cols());
  return s;
}

float displacement_floor(double range, double pose_noise, double pose_noise_deg) {
  constexpr double kRangeNoise = 0.02, kDivergence = 0.003, kSigmas = 3.0;
  const double pose = pose_noise * pose_noise + std::pow(range * pose_noise_deg * M_PI / 180.0, 2);
  const double sigma_sq = 2.0 * pose + kRangeNoise * kRangeNoise + std::pow(kDivergence * range, 2);
  return static_cast<float>(kSigmas * std::sqrt(sigma_sq));
}

}  // namespace cleanmap
