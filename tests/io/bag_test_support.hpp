#pragma once

// What the ROS 1 and ROS 2 bag tests share: the point records they publish and the check that a
// bag reads back as the scans it was made of.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "io/sequence.hpp"
#include "simulation/synthetic_lidar.hpp"

namespace cleanmap::test {

// x y z intensity (float32) and t (uint32, ns after the stamp), 20 bytes a point, as an Ouster
// driver publishes them.
inline std::vector<std::uint8_t> ouster_records(const Scan& scan) {
  std::vector<std::uint8_t> data(scan.size() * 20);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = data.data() + i * 20;
    const auto c = static_cast<Eigen::Index>(i);
    std::memcpy(p, scan.points.col(c).data(), 12);
    std::memcpy(p + 12, &scan.intensity[c], 4);
    const auto ns = static_cast<std::uint32_t>(std::lround(scan.time[c] * 1e9));
    std::memcpy(p + 16, &ns, 4);
  }
  return data;
}

// Every scan of `seq` is the simulated one: points, per-point times (ns -> s) and pose.
inline void expect_same_scans(const Sequence& seq, const std::vector<SyntheticScan>& truth) {
  ASSERT_EQ(seq.size(), truth.size());
  ASSERT_TRUE(seq.has_poses());
  EXPECT_NEAR(seq.times[1] - seq.times[0], 0.1, 1e-6);
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const auto s = load_scan(seq, i);
    EXPECT_EQ(s.scan.name, scan_name(i));
    ASSERT_EQ(s.scan.size(), truth[i].scan.size());
    EXPECT_TRUE(s.scan.points.isApprox(truth[i].scan.points));
    ASSERT_TRUE(s.scan.has_time());
    EXPECT_NEAR((s.scan.time - truth[i].scan.time).cwiseAbs().maxCoeff(), 0.0, 1e-6);
    EXPECT_TRUE(s.scan.pose->isApprox(*truth[i].scan.pose, 1e-6));
  }
}

}  // namespace cleanmap::test
