// KITTI velodyne .bin scans (float32 x y z remission), through a file as the reader takes it.
#include "io/kitti_bin.hpp"
#include "io/scan.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".bin");
  cleanmap::fuzz::expect_clean([&] {
    cleanmap::Scan s = cleanmap::read_kitti_bin(file);
    cleanmap::drop_invalid(s);
  });
  return 0;
}
