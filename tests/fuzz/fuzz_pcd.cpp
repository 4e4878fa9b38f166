// PCD files: header, ascii, binary and binary_compressed bodies, then the record decoding.
#include <string_view>

#include "io/pcd_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cleanmap::fuzz::expect_clean([&] {
    const auto r = cleanmap::parse_pcd(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.pcd");
    cleanmap::scan_from_raw_cloud(r.view(), "fuzz.pcd", cleanmap::TimeUnit::kAuto);
  });
  return 0;
}
