// Per-point times from azimuth: exact on hand-made sweeps cut where a driver cuts them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "odometry/preprocess.hpp"

namespace cleanmap {
namespace {

Eigen::Matrix3Xf at_azimuths(const std::vector<double>& deg) {
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(deg.size()));
  for (std::size_t i = 0; i < deg.size(); ++i) {
    const double a = deg[i] * M_PI / 180.0;
    m.col(static_cast<Eigen::Index>(i)) = Eigen::Vector3f(static_cast<float>(10 * std::cos(a)), static_cast<float>(10 * std::sin(a)), 0.5f);
  }
  return m;
}

TEST(AzimuthTime, ClockwiseFromWhereTheDriverCutTheSweepPastAFullTurn) {
  // A clockwise sweep in firing order from +45 deg (as the Pandar64 street's scans), one
  // column per degree, 390 deg in all; each column's second laser fires 2 deg ahead.
  const double sweep = 0.1;
  std::vector<double> az;
  for (int k = 0; k < 390; ++k) {
    az.push_back(45.0 - k);
    az.push_back(47.0 - k);
  }
  const Eigen::VectorXf t = times_from_azimuth(at_azimuths(az), sweep);
  EXPECT_NEAR(t[1], 0.0, 1e-6);  // ahead of the first point, in its column
  for (int k = 1; k < 390; ++k) {
    EXPECT_NEAR(t[2 * k], sweep * k / 360.0, 1e-6) << k;
    // 2 deg ahead of its column: fired with it, as if 2 deg earlier (never before the start).
    EXPECT_NEAR(t[2 * k + 1], sweep * std::max(0, k - 2) / 360.0, 1e-6) << k;
  }
  // The sector between +x and the cut (0..45 deg) comes at the turn's end, not its start, and
  // the 30 deg past the full turn after that.
  EXPECT_NEAR(t[2 * 45], sweep * 45 / 360.0, 1e-6);    // 0 deg: an eighth of the way
  EXPECT_NEAR(t[2 * 385], sweep * 385 / 360.0, 1e-6);  // 20 deg, the second time
}

TEST(AzimuthTime, NoPointsNoTimes) { EXPECT_EQ(times_from_azimuth(Eigen::Matrix3Xf(3, 0), 0.1).size(), 0); }

}  // namespace
}  // namespace cleanmap
