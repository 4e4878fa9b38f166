// PLY files: header, ascii and both binary bodies, lists, the camera element, then the records.
#include <string_view>

#include "io/ply_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cleanmap::fuzz::expect_clean([&] {
    const auto r = cleanmap::parse_ply(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ply");
    cleanmap::scan_from_raw_cloud(r.view(), "fuzz.ply", cleanmap::TimeUnit::kAuto);
  });
  return 0;
}
