// The depth-sequence text files: camera.yaml (intrinsics), depth.txt (the frame list) and
// rosbag2's metadata.yaml, each read from the same fuzz bytes. Only cleanmap::Error may end
// a read.
#include <unistd.h>

#include "io/depth_image.hpp"
#include "io/depth_sequence.hpp"
#include "io/ros2_bag.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto yaml = cleanmap::fuzz::as_file(data, size, ".yaml");
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_depth_intrinsics(yaml); });
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_depth_list(yaml); });
  // metadata.yaml must sit in a bag folder of its own.
  static const std::filesystem::path folder =
      std::filesystem::path("/dev/shm") / ("cleanmap-fuzz-bag-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  std::filesystem::copy_file(yaml, folder / "metadata.yaml", std::filesystem::copy_options::overwrite_existing);
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_ros2_metadata(folder); });
  return 0;
}
