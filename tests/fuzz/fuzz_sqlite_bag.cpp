// ROS 2 sqlite3 bags: a .db3 built from the fuzz bytes, opened, its topics listed and every
// topic's rows and messages read. Only cleanmap::Error may end it (a schema that defines code,
// a VIEW or a trigger, must never run: see Ros2BagErrors.ASchemaThatDefinesCodeIsNeverRun).
#include "io/sqlite_bag.hpp"
#include "tests/fuzz/fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = cleanmap::fuzz::as_file(data, size, ".db3");
  cleanmap::fuzz::expect_clean([&] {
    const cleanmap::SqliteBagReader bag(file);
    for (const auto& [topic, type] : bag.topic_types()) {
      std::vector<std::vector<std::uint8_t>> heads;
      for (const auto& row : bag.rows(topic, 64, &heads)) bag.read(row.id);
    }
  });
  return 0;
}
