// MCAP files as the ROS 2 bag reader reads them: the data section scanned (chunks decompressed
// with zstd or lz4 and CRC-checked), then every message on every channel read back by its
// reference, as a scan is.
#include <set>

#include "io/mcap_file.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cleanmap;
  const auto file = fuzz::as_file(data, size, ".mcap");
  fuzz::expect_clean([&] {
    McapReader reader(file);
    std::vector<McapMessageRef> refs;
    // Topics are known only once their Channel record is read: a first pass finds them.
    std::set<std::string> topics;
    reader.scan({}, [](const McapChannel&, const McapMessageRef&, const std::uint8_t*, std::size_t) {});
    for (const auto& [id, c] : reader.channels()) topics.insert(c.topic);
    reader.scan(topics, [&](const McapChannel&, const McapMessageRef& m, const std::uint8_t*, std::size_t) {
      refs.push_back(m);
    });
    for (const auto& m : refs) reader.read(m);
  });
  return 0;
}
