// KITTI calib.txt (the Tr velodyne -> camera-0 line).
#include "io/pose_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".txt");
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_kitti_calib_tr(file); });
  return 0;
}
