#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

struct sqlite3;

namespace cleanmap {

// One rosbag2 sqlite3 storage file (.db3), through Debian's libsqlite3: the tables `topics`
// (id, name, type, serialization_format, ...) and `messages` (id, topic_id, timestamp in ns,
// data: the CDR bytes). Opened read-only; a file that is not such a database is an Error
// naming it.
class SqliteBagReader {
 public:
  explicit SqliteBagReader(const std::filesystem::path& file);
  ~SqliteBagReader();
  SqliteBagReader(const SqliteBagReader&) = delete;
  SqliteBagReader& operator=(const SqliteBagReader&) = delete;

  struct Row {
    std::int64_t id, timestamp;
  };
  std::map<std::string, std::string> topic_types() const;  // name -> type
  // Rows of a topic in time order, and the first `head_bytes` of each message (its header; 0:
  // all of it).
  std::vector<Row> rows(const std::string& topic, std::size_t head_bytes, std::vector<std::vector<std::uint8_t>>* heads) const;
  std::vector<std::uint8_t> read(std::int64_t id) const;

 private:
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

// Writes a .db3 with rosbag2's tables (tests build bags with it).
class SqliteBagWriter {
 public:
  explicit SqliteBagWriter(const std::filesystem::path& file);
  ~SqliteBagWriter();
  SqliteBagWriter(const SqliteBagWriter&) = delete;
  SqliteBagWriter& operator=(const SqliteBagWriter&) = delete;

  std::int64_t add_topic(const std::string& name, const std::string& type);
  void add_message(std::int64_t topic, std::int64_t timestamp_ns, const std::vector<std::uint8_t>& data);

 private:
  void exec(const std::string& sql);
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

}  // namespace cleanmap
