// The three real recorded sequences of ../shared/data load through the automatic detection.
#include <map>

#include "io/label_file.hpp"
#include "io/sequence.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

TEST(RealData, KittiSequenceLoadsWithLidarFramePosesAndMovingLabels) {
  const auto seq = open_sequence(test::shared_data() / "kitti00");
  EXPECT_EQ(seq.layout, "kitti");
  ASSERT_EQ(seq.size(), 10u);
  ASSERT_TRUE(seq.calib_tr.has_value());
  ASSERT_TRUE(seq.has_poses());
  // Camera z is forward; in the lidar frame the car drives along +x.
  const Eigen::Vector3d step = seq.poses[1].translation() - seq.poses[0].translation();
  EXPECT_GT(step.x(), 0.8);
  EXPECT_LT(std::abs(step.z()), 0.1);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto s = load_scan(seq, i);
    EXPECT_GT(s.scan.size(), 100000u);
    ASSERT_EQ(s.labels.size(), s.scan.size());
    std::size_t moving = 0, motorcyclist = 0;
    for (auto l : s.labels) {
      moving += is_moving_label(l);
      motorcyclist += semantic_class(l) == 255;
    }
    // The README: a moving motorcyclist of ~70-90 points in scans 0-2.
    EXPECT_GE(motorcyclist, 50u) << "scan " << i;
    EXPECT_LE(motorcyclist, 120u) << "scan " << i;
    EXPECT_EQ(moving, motorcyclist);
  }
  EXPECT_TRUE(seq.labels[5].empty());
}

TEST(RealData, BalmCampusLoadsWithPosesAndEpochTimes) {
  const auto seq = open_sequence(test::shared_data() / "balm_campus");
  EXPECT_EQ(seq.layout, "scans-folder");
  ASSERT_EQ(seq.size(), 40u);
  EXPECT_TRUE(seq.has_poses());
  EXPECT_NEAR(seq.times[1] - seq.times[0], 0.5, 0.01);
  const auto s = load_scan(seq, 0);
  EXPECT_GT(s.scan.size(), 50000u);
  EXPECT_TRUE(s.scan.has_intensity());
}

TEST(RealData, Pandar64StreetLoadsWithGreyIntensityFromRgb) {
  const auto seq = open_sequence(test::shared_data() / "pandar64_street");
  EXPECT_EQ(seq.size(), 30u);
  EXPECT_FALSE(seq.has_poses());
  const auto s = load_scan(seq, 0);
  EXPECT_GT(s.scan.size(), 200000u);
  ASSERT_TRUE(s.scan.has_intensity());
  EXPECT_GT(s.scan.intensity.maxCoeff(), 0.0f);
  EXPECT_LE(s.scan.intensity.maxCoeff(), 255.0f);
}

}  // namespace
}  // namespace cleanmap
