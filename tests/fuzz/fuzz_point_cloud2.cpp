// sensor_msgs/PointCloud2 decoding as the bag reader does it: the layout a message declares
// (fields with offsets and type codes, point_step, width x height) over the bytes it carries.
// Input: [fields n][n x (name index, offset u32, type u8)][point_step u32][points u32][data].
#include <cstring>

#include "io/raw_cloud.hpp"
#include "tests/fuzz/fuzz_file.hpp"

namespace {

template <typename T>
bool take(const std::uint8_t*& p, std::size_t& left, T& out) {
  if (left < sizeof(T)) return false;
  std::memcpy(&out, p, sizeof(T));
  p += sizeof(T);
  left -= sizeof(T);
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char* const kNames[] = {"x", "y", "z", "intensity", "t", "time", "rgb", "ring"};
  const std::uint8_t* p = data;
  std::size_t left = size;
  std::uint8_t n = 0;
  if (!take(p, left, n)) return 0;
  cleanmap::RawCloud cloud;
  for (int k = 0; k < n % 9; ++k) {
    std::uint8_t name = 0, type = 0;
    std::uint32_t offset = 0;
    if (!take(p, left, name) || !take(p, left, offset) || !take(p, left, type)) return 0;
    cloud.fields.push_back({kNames[name % 8], offset, type});
  }
  std::uint32_t step = 0, points = 0;
  if (!take(p, left, step) || !take(p, left, points)) return 0;
  cloud.point_step = step;
  cloud.points = points;
  cloud.data = p;
  cloud.bytes = left;
  cleanmap::fuzz::expect_clean([&] { cleanmap::scan_from_raw_cloud(cloud, "fuzz:/points#0", cleanmap::TimeUnit::kAuto); });
  return 0;
}
