// Pose files (KITTI 3x4, TUM, detected) and time files.
#include "io/pose_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".txt");
  for (auto format : {cleanmap::PoseFormat::kAuto, cleanmap::PoseFormat::kKitti, cleanmap::PoseFormat::kTum}) {
    cleanmap::fuzz::expect_clean([&] { cleanmap::read_poses(file, format); });
  }
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_times(file); });
  return 0;
}
