#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <array>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace cleanmap {

// MCAP (the openly specified container rosbag2 writes by default since Iron), read and written
// by hand: Debian has no MCAP library. Records are <opcode u8><length u64><content>, little-
// endian; messages sit in the data section or inside Chunk records, which may be compressed
// with zstd or lz4 (frame format), Debian's libzstd and liblz4. Only what a reader of a log
// needs is read: Schema, Channel, Message and Chunk records of the data section, in file order
// (the summary and its indexes are optional in the format and not needed for that).
//
// Every length is checked against the file (or the decompressed chunk) before it is used, and
// a chunk may claim at most kMaxChunkExpansion times its compressed size when decompressed.

struct McapChannel {
  std::uint16_t id = 0;
  std::string topic, message_encoding, schema_name, schema_encoding;
};

// Where one message's bytes are: in the file itself, or inside a chunk (offsets into the
// decompressed records).
struct McapMessageRef {
  static constexpr std::uint64_t kNoChunk = ~std::uint64_t{0};
  std::uint64_t chunk = kNoChunk;  // file offset of the chunk record
  std::uint64_t offset = 0, size = 0;
  std::uint64_t log_time = 0;      // ns
  std::uint16_t channel = 0;
};

inline constexpr std::uint64_t kMaxChunkExpansion = 1000;  // real lidar chunks: 2-5x

class McapReader {
 public:
  explicit McapReader(const std::filesystem::path& file);

  using OnMessage = std::function<void(const McapChannel&, const McapMessageRef&, const std::uint8_t*, std::size_t)>;
  // Reads the data section once, calling `on_message` for every message on one of `topics`.
  void scan(const std::set<std::string>& topics, const OnMessage& on_message);
  std::vector<std::uint8_t> read(const McapMessageRef& message) const;
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }

 private:
  struct Record {
    std::uint8_t opcode;
    std::uint64_t start, content, length;  // record start, content start, content length
  };
  Record next_record(std::uint64_t at) const;
  std::vector<std::uint8_t> bytes_at(std::uint64_t at, std::uint64_t n) const;
  std::vector<std::uint8_t> chunk_records(std::uint64_t chunk) const;
  void inner_records(const std::vector<std::uint8_t>& records, std::uint64_t chunk, const std::set<std::string>& topics,
                     const OnMessage& on_message);
  void take_schema_or_channel(std::uint8_t opcode, const std::uint8_t* p, std::size_t n);

  std::filesystem::path file_;
  mutable std::ifstream in_;
  mutable std::mutex mutex_;
  std::uint64_t size_ = 0;
  std::map<std::uint16_t, std::pair<std::string, std::string>> schemas_;  // id -> name, encoding
  std::map<std::uint16_t, McapChannel> channels_;
  mutable std::uint64_t cached_chunk_ = McapMessageRef::kNoChunk;
  mutable std::vector<std::uint8_t> cached_records_;
};

enum class McapCompression { kNone, kZstd, kLz4 };

// Writes an MCAP file the way rosbag2 lays one out: Header, chunks of Schema/Channel/Message
// records each followed by its Message Index records, Data End, a summary (Schema, Channel,
// Chunk Index, Statistics) and the Footer. Messages are added in log-time order.
class McapWriter {
 public:
  McapWriter(const std::filesystem::path& file, McapCompression compression, std::size_t chunk_bytes = 1 << 20);
  ~McapWriter();
  // A ROS 2 type; `encoding`, the messages' (rosbag2 writes cdr; others only to test readers).
  std::uint16_t add_channel(const std::string& topic, const std::string& type, const std::string& encoding = "cdr");
  void add_message(std::uint16_t channel, std::uint64_t log_time_ns, const std::vector<std::uint8_t>& data);
  void close();

 private:
  void flush_chunk();
  void record(std::vector<std::uint8_t>& out, std::uint8_t opcode, const std::vector<std::uint8_t>& content);

  std::filesystem::path path_;
  std::ofstream out_;
  McapCompression compression_;
  std::size_t chunk_bytes_;
  std::uint64_t written_ = 0;
  std::vector<std::uint8_t> chunk_, summary_chunk_indexes_, schemas_channels_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::set<std::uint16_t> in_chunk_;  // channels whose schema and channel records this chunk holds
  std::map<std::uint16_t, std::array<std::string, 3>> channel_info_;  // topic, type, encoding
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0, first_ = 0, last_ = 0, messages_ = 0, chunks_ = 0;
  std::uint32_t sequence_ = 0;
  bool closed_ = false;
};

}  // namespace cleanmap
