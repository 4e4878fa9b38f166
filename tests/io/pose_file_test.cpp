#include "io/pose_file.hpp"

#include <fstream>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

std::vector<Eigen::Isometry3d> some_poses() {
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 4; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translate(Eigen::Vector3d(i, 0.5 * i, -0.1 * i));
    p.rotate(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(0.2, 0.3, 1).normalized()));
    poses.push_back(p);
  }
  return poses;
}

TEST(PoseFile, KittiRoundTrip) {
  test::TempDir dir;
  const auto poses = some_poses();
  write_kitti_poses(dir / "p.txt", poses);
  const auto r = read_poses(dir / "p.txt");
  ASSERT_EQ(r.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_TRUE(std::isnan(r[i].stamp));
    EXPECT_TRUE(r[i].pose.isApprox(poses[i], 1e-8));
  }
}

TEST(PoseFile, TumRoundTripKeepsStamps) {
  test::TempDir dir;
  std::vector<StampedPose> poses;
  for (const auto& p : some_poses()) poses.push_back({1630577758.5 + 0.1 * poses.size(), p});
  write_tum_poses(dir / "p.tum", poses);
  const auto r = read_poses(dir / "p.tum");
  ASSERT_EQ(r.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(r[i].stamp, poses[i].stamp, 1e-6);
    EXPECT_TRUE(r[i].pose.isApprox(poses[i].pose, 1e-8));
  }
}

TEST(PoseFile, WrongColumnCountIsAnError) {
  test::TempDir dir;
  std::ofstream(dir / "bad.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n";
  test::expect_error([&] { read_poses(dir / "bad.txt"); }, {"bad.txt", "line 2", "11 columns"});
  std::ofstream(dir / "odd.txt") << "1 2 3\n";
  test::expect_error([&] { read_poses(dir / "odd.txt"); }, {"odd.txt", "3 columns"});
}

TEST(PoseFile, NonNumbersAreAnError) {
  test::TempDir dir;
  std::ofstream(dir / "nan.txt") << "0 1 2 3 0 0 0 nan\n";
  test::expect_error([&] { read_poses(dir / "nan.txt"); }, {"nan.txt", "line 1", "not a finite"});
}

TEST(PoseFile, CalibTrIsRead) {
  const auto tr = read_kitti_calib_tr(test::shared_data() / "kitti00" / "calib.txt");
  EXPECT_NEAR(tr.translation().z(), -0.2921968648686, 1e-9);
  EXPECT_NEAR(tr.linear().determinant(), 1.0, 1e-9);
}

}  // namespace
}  // namespace cleanmap
