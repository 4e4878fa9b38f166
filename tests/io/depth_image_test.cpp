// Depth images: 16-bit PNG round trips, exact back-projection, the camera file's checks, and the
// TUM RGB-D layout read as a sequence (the synthetic table scene, whose truth is known).
#include <zlib.h>

#include <cmath>
#include <fstream>

#include "io/depth_image.hpp"
#include "io/depth_sequence.hpp"
#include "io/label_file.hpp"
#include "io/pose_file.hpp"
#include "simulation/synthetic_depth.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;

TEST(DepthImage, SixteenBitPngRoundTripsExactly) {
  test::TempDir dir;
  Image16 img{5, 3, {}};
  for (int i = 0; i < 15; ++i) img.pixels.push_back(static_cast<std::uint16_t>(i * 4369));  // 0 .. 61166
  write_png16(dir / "d.png", img);
  const auto back = read_png16(dir / "d.png");
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.pixels, img.pixels);
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
}

// A PNG chunk: length, type and data, CRC over type and data.
std::string chunk(const std::string& type, const std::string& data) {
  std::string out;
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  const auto crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
  out += body;
  put_u32(out, static_cast<std::uint32_t>(crc));
  return out;
}

// A PNG whose header claims the given size and format; `with_data` adds an empty IDAT (so a
// reader gets past the header) and IEND, else the file ends after the header.
std::string png_header(std::uint32_t w, std::uint32_t h, std::uint8_t depth, std::uint8_t colour, bool with_data = false) {
  std::string ihdr;
  put_u32(ihdr, w);
  put_u32(ihdr, h);
  ihdr += std::string{static_cast<char>(depth), static_cast<char>(colour), 0, 0, 0};
  std::string out = "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr);
  if (with_data) out += chunk("IDAT", "") + chunk("IEND", "");
  return out;
}

TEST(DepthImage, BadPngsAreClearErrorsBeforeAnyAllocation) {
  test::TempDir dir;
  std::ofstream(dir / "rgb.png", std::ios::binary) << png_header(4, 4, 8, 2, true);
  test::expect_error([&] { read_png16(dir / "rgb.png"); }, {"rgb.png", "not a 16-bit greyscale image"});
  std::ofstream(dir / "huge.png", std::ios::binary) << png_header(100000, 100000, 16, 0);  // 20 GB of pixels
  test::expect_error([&] { read_png16(dir / "huge.png"); }, {"huge.png", "unreadable PNG"});
  // Within libpng's side limit, but 0.5 GB of samples (issue 45: allocated from a 0.5 MB file).
  std::ofstream(dir / "wide.png", std::ios::binary) << png_header(16384, 16384, 16, 0, true);
  test::expect_error([&] { read_png16(dir / "wide.png"); }, {"wide.png", "16384 x 16384 pixels: more than the 8388608"});
  std::ofstream(dir / "cut.png", std::ios::binary) << png_header(64, 64, 16, 0);  // no pixel data
  test::expect_error([&] { read_png16(dir / "cut.png"); }, {"cut.png", "unreadable PNG"});
  std::ofstream(dir / "text.png") << "not a png";
  test::expect_error([&] { read_png16(dir / "text.png"); }, {"text.png"});
  test::expect_error([&] { read_png16(dir / "missing.png"); }, {"missing.png", "cannot open"});
}

TEST(DepthImage, BackProjectionIsThePinholeModelExactly) {
  DepthIntrinsics k;
  k.fx = 500;
  k.fy = 400;
  k.cx = 2;
  k.cy = 1;
  k.depth_scale = 1000;
  k.max_depth = 3;
  Image16 d{4, 3, std::vector<std::uint16_t>(12, 0)};
  d.pixels[1 * 4 + 2] = 1500;  // the principal point at 1.5 m
  d.pixels[2 * 4 + 3] = 2000;  // one pixel right and down of it at 2 m
  d.pixels[0] = 3500;          // beyond max_depth
  const Scan s = depth_to_scan(d, k);
  ASSERT_EQ(s.size(), 12u);  // one point per pixel, in image order
  EXPECT_TRUE(s.points.col(6).isApprox(Eigen::Vector3f(0, 0, 1.5f)));
  EXPECT_TRUE(s.points.col(11).isApprox(Eigen::Vector3f(2.0f * 1 / 500, 2.0f * 1 / 400, 2.0f)));
  EXPECT_TRUE(std::isnan(s.points(0, 0)));  // too far
  EXPECT_TRUE(std::isnan(s.points(0, 1)));  // no depth
  // Distortion: a point pushed through the model comes back from undistort.
  k.distortion = std::array<double, 5>{-0.2, 0.05, 0.001, -0.002, 0.0};
  const double x = 0.3, y = -0.2, r2 = x * x + y * y, radial = 1 - 0.2 * r2 + 0.05 * r2 * r2;
  const double xd = x * radial + 2 * 0.001 * x * y - 0.002 * (r2 + 2 * x * x);
  const double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.002 * x * y;
  const auto [ux, uy] = undistort(k, k.cx + k.fx * xd, k.cy + k.fy * yd);
  EXPECT_NEAR(ux, x, 1e-9);
  EXPECT_NEAR(uy, y, 1e-9);
}

TEST(DepthImage, TheCameraFileIsChecked) {
  test::TempDir dir;
  auto expect = [&](const std::string& yaml, std::initializer_list<std::string> words) {
    std::ofstream(dir / "camera.yaml") << yaml;
    test::expect_error([&] { read_depth_intrinsics(dir / "camera.yaml"); }, words);
  };
  expect("fx: 500\nfy: 500\ncx: 1\ncy: 1\nfocal: 3\n", {"camera.yaml", "unknown key 'focal'"});
  expect("fx: .nan\nfy: 500\ncx: 1\ncy: 1\n", {"camera.yaml", "fx: must be finite"});
  expect("fy: 500\ncx: 1\ncy: 1\n", {"camera.yaml", "fx and fy must be given"});
  expect("fy: 500\n[fx, cx]: 1\n", {"camera.yaml", "a key that is a list or a map", "line 2"});  // was a bad conversion
  expect("fx: 5\nfy: 5\ncx: 1\ncy: 1\ndistortion: [1, 2]\n", {"camera.yaml", "five numbers"});
  expect("fx: 5\nfy: 5\ncx: 1\ncy: 1\ndepth_scale: 0\n", {"camera.yaml", "depth_scale must be positive"});
  test::expect_error([&] { read_depth_intrinsics(dir / "none.yaml"); }, {"none.yaml", "no such camera file"});
}

TEST(DepthSequence, TheTableSceneReadsBackWithItsPosesAndPixelLabels) {
  test::TempDir dir;
  const auto scene = make_table_scene();
  write_table_sequence(dir / "seq", scene, 5, 30.0, 3);
  const auto seq = open_sequence(dir / "seq");
  EXPECT_EQ(seq.layout, "tum-rgbd");
  ASSERT_EQ(seq.size(), 5u);
  EXPECT_EQ(seq.image_width, 320);
  EXPECT_EQ(seq.image_height, 240);
  EXPECT_NEAR(seq.times[1] - seq.times[0], 1.0 / 30, 1e-6);
  ASSERT_TRUE(seq.has_poses());
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const double t = static_cast<double>(i) / 30;
    EXPECT_TRUE(seq.poses[i].isApprox(depth_camera_pose(scene, t), 1e-6)) << i;
    const auto s = load_scan(seq, i);
    EXPECT_EQ(s.scan.size() + s.dropped_non_finite, 320u * 240u);  // one point per pixel
    ASSERT_EQ(s.labels.size(), s.scan.size());
    EXPECT_GT(std::count(s.labels.begin(), s.labels.end(), kLabelMoving), 1000);
    // The table top is 0.75 m above the floor: the world-frame heights of its pixels say so.
    const Eigen::Matrix3Xf world = (seq.poses[i].cast<float>() * s.scan.points).eval();
    std::size_t table = 0;
    for (Eigen::Index c = 0; c < world.cols(); ++c) table += std::abs(world(2, c) - 0.75f) < 0.01f;
    EXPECT_GT(table, 10000u) << i;
  }
}

TEST(DepthSequence, BadListsAndUncoveredPosesAreClearErrors) {
  test::TempDir dir;
  write_table_sequence(dir / "seq", make_table_scene(), 4, 30.0, 3);
  std::ofstream(dir / "seq" / "depth.txt", std::ios::app) << "99.0 depth/x.png\n";
  test::expect_error([&] { open_sequence(dir / "seq"); }, {"depth.txt", "line 7", "stamps must increase"});
  write_table_sequence(dir / "b", make_table_scene(), 4, 30.0, 3);
  auto poses = read_poses(dir / "b" / "groundtruth.txt");
  poses.resize(2);  // the track ends after frame 1
  write_tum_poses(dir / "b" / "groundtruth.txt", poses);
  test::expect_error([&] { open_sequence(dir / "b"); }, {"groundtruth.txt", "frame 2 is at", "trim depth.txt"});
  fs::remove(dir / "b" / "camera.yaml");
  fs::remove(dir / "b" / "groundtruth.txt");
  test::expect_error([&] { open_sequence(dir / "b"); }, {"camera.yaml", "no such camera file"});
  // A principal point thousands of image widths away (issue 45: accepted).
  write_table_sequence(dir / "c", make_table_scene(), 2, 30.0, 3);
  auto k = read_depth_intrinsics(dir / "c" / "camera.yaml");
  k.cx = 3000 * 320.0;
  write_depth_intrinsics(dir / "c" / "camera.yaml", k);
  test::expect_error([&] { open_sequence(dir / "c"); }, {"camera.yaml", "principal point", "far outside the 320 x 240"});
}

}  // namespace
}  // namespace cleanmap
