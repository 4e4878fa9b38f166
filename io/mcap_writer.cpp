#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "io/error.hpp"
#include "io/mcap_file.hpp"
#include "io/mcap_records.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
using namespace mcap;

namespace {

std::vector<std::uint8_t> compress(McapCompression c, const std::vector<std::uint8_t>& in) {
  if (c == McapCompression::kNone) return in;
  std::vector<std::uint8_t> out;
  if (c == McapCompression::kZstd) {
    out.resize(ZSTD_compressBound(in.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3);
    if (ZSTD_isError(n)) throw Error(std::string("zstd: ") + ZSTD_getErrorName(n));
    out.resize(n);
  } else {
    out.resize(LZ4F_compressFrameBound(in.size(), nullptr));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr);
    if (LZ4F_isError(n)) throw Error(std::string("lz4: ") + LZ4F_getErrorName(n));
    out.resize(n);
  }
  return out;
}

const char* name_of(McapCompression c) { return c == McapCompression::kZstd ? "zstd" : c == McapCompression::kLz4 ? "lz4" : ""; }

}  // namespace

McapWriter::McapWriter(const fs::path& file, McapCompression compression, std::size_t chunk_bytes)
    : path_(file), out_(file, std::ios::binary), compression_(compression), chunk_bytes_(chunk_bytes) {
  if (!out_) fail(file, "cannot create file");
  std::vector<std::uint8_t> head(kMagic, kMagic + 8), header;
  put_string(header, "ros2");
  put_string(header, "cleanmap");
  record(head, kHeader, header);
  out_.write(reinterpret_cast<const char*>(head.data()), static_cast<std::streamsize>(head.size()));
  written_ = head.size();
}

McapWriter::~McapWriter() {
  if (!closed_) {
    try {
      close();
    } catch (const std::exception&) {
      // a destructor must not throw; close() reports failures to callers that call it
    }
  }
}

void McapWriter::record(std::vector<std::uint8_t>& out, std::uint8_t opcode, const std::vector<std::uint8_t>& content) {
  out.push_back(opcode);
  put<std::uint64_t>(out, content.size());
  out.insert(out.end(), content.begin(), content.end());
}

std::uint16_t McapWriter::add_channel(const std::string& topic, const std::string& type, const std::string& encoding) {
  const auto id = static_cast<std::uint16_t>(channel_info_.size() + 1);
  channel_info_[id] = {topic, type, encoding};
  return id;
}

void McapWriter::add_message(std::uint16_t channel, std::uint64_t log_time_ns, const std::vector<std::uint8_t>& data) {
  const auto& [topic, type, encoding] = channel_info_.at(channel);
  if (!in_chunk_.count(channel)) {  // each chunk carries the schema and channel of what it holds
    std::vector<std::uint8_t> schema, chan;
    put<std::uint16_t>(schema, channel);
    put_string(schema, type);
    put_string(schema, "ros2msg");
    put<std::uint32_t>(schema, 0);  // no message definition text
    put<std::uint16_t>(chan, channel);
    put<std::uint16_t>(chan, channel);
    put_string(chan, topic);
    put_string(chan, encoding);
    put<std::uint32_t>(chan, 0);  // no metadata
    record(chunk_, kSchema, schema);
    record(chunk_, kChannel, chan);
    if (!counts_.count(channel)) {
      record(schemas_channels_, kSchema, schema);
      record(schemas_channels_, kChannel, chan);
    }
    in_chunk_.insert(channel);
  }
  if (chunk_index_.empty()) chunk_start_ = log_time_ns;  // the chunk's first message
  chunk_index_[channel].push_back({log_time_ns, chunk_.size()});
  std::vector<std::uint8_t> m;
  put<std::uint16_t>(m, channel);
  put<std::uint32_t>(m, sequence_++);
  put<std::uint64_t>(m, log_time_ns);
  put<std::uint64_t>(m, log_time_ns);
  m.insert(m.end(), data.begin(), data.end());
  record(chunk_, kMessage, m);
  chunk_end_ = log_time_ns;
  if (messages_ == 0) first_ = log_time_ns;
  last_ = log_time_ns;
  ++messages_;
  ++counts_[channel];
  if (chunk_.size() >= chunk_bytes_) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  const auto packed = compress(compression_, chunk_);
  std::vector<std::uint8_t> c, rec;
  put<std::uint64_t>(c, chunk_start_);
  put<std::uint64_t>(c, chunk_end_);
  put<std::uint64_t>(c, chunk_.size());
  put<std::uint32_t>(c, static_cast<std::uint32_t>(crc32(0L, chunk_.data(), static_cast<uInt>(chunk_.size()))));
  put_string(c, name_of(compression_));
  put<std::uint64_t>(c, packed.size());
  c.insert(c.end(), packed.begin(), packed.end());
  const std::uint64_t chunk_at = written_;
  record(rec, kChunk, c);
  const std::uint64_t chunk_length = rec.size();
  std::vector<std::uint8_t> offsets;  // the chunk index's map: channel -> message index offset
  for (const auto& [channel, entries] : chunk_index_) {
    put<std::uint16_t>(offsets, channel);
    put<std::uint64_t>(offsets, chunk_at + rec.size());
    std::vector<std::uint8_t> index;
    put<std::uint16_t>(index, channel);
    put<std::uint32_t>(index, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, off] : entries) {
      put<std::uint64_t>(index, t);
      put<std::uint64_t>(index, off);
    }
    record(rec, kMessageIndex, index);
  }
  std::vector<std::uint8_t> ci;
  put<std::uint64_t>(ci, chunk_start_);
  put<std::uint64_t>(ci, chunk_end_);
  put<std::uint64_t>(ci, chunk_at);
  put<std::uint64_t>(ci, chunk_length);
  put<std::uint32_t>(ci, static_cast<std::uint32_t>(offsets.size()));
  ci.insert(ci.end(), offsets.begin(), offsets.end());
  put<std::uint64_t>(ci, rec.size() - chunk_length);
  put_string(ci, name_of(compression_));
  put<std::uint64_t>(ci, packed.size());
  put<std::uint64_t>(ci, chunk_.size());
  record(summary_chunk_indexes_, kChunkIndex, ci);
  out_.write(reinterpret_cast<const char*>(rec.data()), static_cast<std::streamsize>(rec.size()));
  written_ += rec.size();
  chunk_.clear();
  chunk_index_.clear();
  in_chunk_.clear();
  ++chunks_;
}

void McapWriter::close() {
  if (closed_) return;
  closed_ = true;
  flush_chunk();
  std::vector<std::uint8_t> tail, data_end, stats;
  put<std::uint32_t>(data_end, 0);  // no data section CRC
  record(tail, kDataEnd, data_end);
  const std::uint64_t summary_start = written_ + tail.size();
  tail.insert(tail.end(), schemas_channels_.begin(), schemas_channels_.end());
  tail.insert(tail.end(), summary_chunk_indexes_.begin(), summary_chunk_indexes_.end());
  put<std::uint64_t>(stats, messages_);
  put<std::uint16_t>(stats, static_cast<std::uint16_t>(counts_.size()));
  put<std::uint32_t>(stats, static_cast<std::uint32_t>(counts_.size()));
  put<std::uint32_t>(stats, 0);
  put<std::uint32_t>(stats, 0);
  put<std::uint32_t>(stats, static_cast<std::uint32_t>(chunks_));
  put<std::uint64_t>(stats, first_);
  put<std::uint64_t>(stats, last_);
  put<std::uint32_t>(stats, static_cast<std::uint32_t>(counts_.size() * 10));
  for (const auto& [channel, n] : counts_) {
    put<std::uint16_t>(stats, channel);
    put<std::uint64_t>(stats, n);
  }
  record(tail, kStatistics, stats);
  std::vector<std::uint8_t> footer;
  put<std::uint64_t>(footer, summary_start);
  put<std::uint64_t>(footer, 0);  // no summary offset section
  put<std::uint32_t>(footer, 0);  // no summary CRC
  record(tail, kFooter, footer);
  tail.insert(tail.end(), kMagic, kMagic + 8);
  out_.write(reinterpret_cast<const char*>(tail.data()), static_cast<std::streamsize>(tail.size()));
  out_.close();
  if (!out_) fail(path_, "write failed");
}

}  // namespace cleanmap
