// Depth images as the TUM RGB-D reader reads them (libpng, 16-bit greyscale only, at most
// kMaxImageSide pixels a side), then back-projected with a fixed camera.
#include "io/depth_image.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cleanmap;
  const auto file = fuzz::as_file(data, size, ".png");
  fuzz::expect_clean([&] {
    const Image16 img = read_png16(file);
    DepthIntrinsics k;
    k.fx = k.fy = 500;
    k.cx = img.width / 2.0;
    k.cy = img.height / 2.0;
    depth_to_scan(img, k);
  });
  return 0;
}
