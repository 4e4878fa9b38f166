// SemanticKITTI .label files, with and without an expected point count (the first byte).
#include "io/label_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".label");
  cleanmap::fuzz::expect_clean([&] { cleanmap::read_labels(file); });
  if (size > 0) cleanmap::fuzz::expect_clean([&] { cleanmap::read_labels(file, data[0]); });
  return 0;
}
