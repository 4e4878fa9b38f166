#include "io/sqlite_bag.hpp"

#include <sqlite3.h>

#include <algorithm>

#include "io/error.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

// A prepared statement, finalised at scope exit.
struct Statement {
  sqlite3_stmt* s = nullptr;
  Statement(sqlite3* db, const std::string& sql, const fs::path& file) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
      fail(file, std::string("not a rosbag2 sqlite3 file (") + sqlite3_errmsg(db) + ")");
    }
  }
  ~Statement() { sqlite3_finalize(s); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
};

std::vector<std::uint8_t> blob(sqlite3_stmt* s, int column) {
  const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, column));
  const int n = sqlite3_column_bytes(s, column);
  return p ? std::vector<std::uint8_t>(p, p + n) : std::vector<std::uint8_t>{};
}

std::string text(sqlite3_stmt* s, int column) {
  const auto* p = sqlite3_column_text(s, column);
  return p ? reinterpret_cast<const char*>(p) : "";
}

}  // namespace

SqliteBagReader::SqliteBagReader(const fs::path& file) : file_(file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) fail(file, "no such sqlite3 bag file");
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    fail(file, "cannot open as sqlite3 (" + why + ")");
  }
  try {
    // The file is data, never code (issue 45: a 4 KB .db3 whose `messages` was a VIEW over an
    // endless recursive query hung the run; another's VIEW made a 900 MB blob). What a schema
    // defines runs with no trust (no functions with side effects), no value is longer than the
    // file, and topics and messages must be the plain tables rosbag2 writes.
    sqlite3_db_config(db_, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
    const auto bytes = fs::file_size(file, ec);
    sqlite3_limit(db_, SQLITE_LIMIT_LENGTH, static_cast<int>(std::min<std::uintmax_t>(ec ? 1 : std::max<std::uintmax_t>(bytes, 1), 1u << 30)));
    {
      Statement schema(db_, "SELECT name, type, sql FROM sqlite_master WHERE name IN ('topics', 'messages')", file_);
      int tables = 0;
      while (sqlite3_step(schema.s) == SQLITE_ROW) {
        const std::string name = text(schema.s, 0), type = text(schema.s, 1), sql = text(schema.s, 2);
        if (type != "table" || sql.rfind("CREATE TABLE", 0) != 0) {
          fail(file, "'" + name + "' is a " + (type == "table" ? "virtual table" : type) +
                         ", not the table rosbag2 writes: not read (the file's own code is never run)");
        }
        ++tables;
      }
      if (tables != 2) fail(file, "not a rosbag2 sqlite3 file (no 'topics' and 'messages' tables)");
    }
    Statement check(db_, "SELECT count(*) FROM topics", file_);  // a random file fails here
    if (sqlite3_step(check.s) != SQLITE_ROW) fail(file, std::string("unreadable (") + sqlite3_errmsg(db_) + ")");
  } catch (...) {  // no destructor runs for a constructor that throws: close here
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

SqliteBagReader::~SqliteBagReader() { sqlite3_close(db_); }

std::map<std::string, std::string> SqliteBagReader::topic_types() const {
  Statement st(db_, "SELECT name, type FROM topics", file_);
  std::map<std::string, std::string> out;
  while (sqlite3_step(st.s) == SQLITE_ROW) out[text(st.s, 0)] = text(st.s, 1);
  return out;
}

std::vector<SqliteBagReader::Row> SqliteBagReader::rows(const std::string& topic, std::size_t head_bytes,
                                                       std::vector<std::vector<std::uint8_t>>* heads) const {
  // substr on a blob is byte-wise: only each message's header is read here, not its cloud.
  Statement st(db_,
               std::string("SELECT m.id, m.timestamp, ") + (head_bytes ? "substr(m.data, 1, ?)" : "m.data, ?") +
                   " FROM messages m JOIN topics t ON m.topic_id = t.id WHERE t.name = ? ORDER BY m.timestamp, m.id",
               file_);
  sqlite3_bind_int64(st.s, 1, static_cast<sqlite3_int64>(head_bytes));
  sqlite3_bind_text(st.s, 2, topic.c_str(), -1, SQLITE_TRANSIENT);
  std::vector<Row> out;
  int rc;
  while ((rc = sqlite3_step(st.s)) == SQLITE_ROW) {
    out.push_back({sqlite3_column_int64(st.s, 0), sqlite3_column_int64(st.s, 1)});
    if (heads) heads->push_back(blob(st.s, 2));
  }
  if (rc != SQLITE_DONE) fail(file_, std::string("unreadable messages (") + sqlite3_errmsg(db_) + "): truncated or corrupt?");
  return out;
}

std::vector<std::uint8_t> SqliteBagReader::read(std::int64_t id) const {
  Statement st(db_, "SELECT data FROM messages WHERE id = ?", file_);
  sqlite3_bind_int64(st.s, 1, id);
  if (sqlite3_step(st.s) != SQLITE_ROW) {
    fail(file_, "message " + std::to_string(id) + " is unreadable (" + sqlite3_errmsg(db_) + ")");
  }
  return blob(st.s, 0);
}

SqliteBagWriter::SqliteBagWriter(const fs::path& file) : file_(file) {
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    sqlite3_close(db_);
    db_ = nullptr;
    fail(file, "cannot create");
  }
  // rosbag2's schema version 4 tables (the columns readers use, and the NOT NULL ones around them).
  try {
    exec("CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
         "INSERT INTO schema VALUES (4, 'cleanmap');"
         "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);"
         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
         "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL, type_description_hash TEXT NOT NULL);"
         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
         "data BLOB NOT NULL);"
         "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

SqliteBagWriter::~SqliteBagWriter() { sqlite3_close(db_); }

void SqliteBagWriter::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "?";
    sqlite3_free(err);
    fail(file_, "sqlite: " + why);
  }
}

std::int64_t SqliteBagWriter::add_topic(const std::string& name, const std::string& type) {
  Statement st(db_, "INSERT INTO topics(name, type, serialization_format, offered_qos_profiles, type_description_hash) "
                    "VALUES (?, ?, 'cdr', '', '')", file_);
  sqlite3_bind_text(st.s, 1, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st.s, 2, type.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(st.s) != SQLITE_DONE) fail(file_, std::string("sqlite: ") + sqlite3_errmsg(db_));
  return sqlite3_last_insert_rowid(db_);
}

void SqliteBagWriter::add_message(std::int64_t topic, std::int64_t timestamp_ns, const std::vector<std::uint8_t>& data) {
  Statement st(db_, "INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)", file_);
  sqlite3_bind_int64(st.s, 1, topic);
  sqlite3_bind_int64(st.s, 2, timestamp_ns);
  sqlite3_bind_blob(st.s, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
  if (sqlite3_step(st.s) != SQLITE_DONE) fail(file_, std::string("sqlite: ") + sqlite3_errmsg(db_));
}

}  // namespace cleanmap
