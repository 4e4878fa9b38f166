// ROS 2 messages as the ROS 2 bag reader decodes them (CDR, either byte order): the input is one
// message's bytes, tried as PointCloud2 (then turned into a scan, its point records swapped when
// it says big-endian), Odometry, TransformStamped and TFMessage.
#include <vector>

#include "io/raw_cloud.hpp"
#include "io/ros2_messages.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cleanmap;
  fuzz::expect_clean([&] {
    const PointCloud2Msg m = decode_point_cloud2(data, size, "fuzz:/points#0");
    std::vector<std::uint8_t> storage;
    scan_from_raw_cloud(raw_cloud_of(m, storage), "fuzz:/points#0", TimeUnit::kAuto);
  });
  fuzz::expect_clean([&] { decode_odometry(data, size, "fuzz:/odom#0"); });
  fuzz::expect_clean([&] { decode_transform_stamped(data, size, "fuzz:/tf#0"); });
  fuzz::expect_clean([&] { decode_tf_message(data, size, "fuzz:/tf#0"); });
  return 0;
}
