#include "io/mcap_file.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "io/error.hpp"
#include "io/mcap_records.hpp"
#include "io/zstd_frame.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
using namespace mcap;

namespace {

std::vector<std::uint8_t> unlz4(const std::uint8_t* src, std::size_t n, std::uint64_t want, const std::string& what) {
  std::vector<std::uint8_t> out(want);
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) throw Error(what + ": lz4: no context");
  std::size_t in_pos = 0, out_pos = 0, hint = 1;
  while (hint != 0 && in_pos < n) {
    std::size_t in_n = n - in_pos, out_n = out.size() - out_pos;
    hint = LZ4F_decompress(ctx, out.data() + out_pos, &out_n, src + in_pos, &in_n, nullptr);
    if (LZ4F_isError(hint)) {
      LZ4F_freeDecompressionContext(ctx);
      throw Error(what + ": lz4: " + LZ4F_getErrorName(hint) + " (truncated or corrupt)");
    }
    in_pos += in_n;
    out_pos += out_n;
    if (in_n == 0 && out_n == 0) break;  // no progress: the output is full or the input cut
  }
  LZ4F_freeDecompressionContext(ctx);
  if (hint != 0 || out_pos != want) {
    throw Error(what + ": lz4 frame " + (hint != 0 ? "cut short" : "of the wrong size") + " (" + std::to_string(out_pos) +
                " of " + std::to_string(want) + " bytes)");
  }
  return out;
}

}  // namespace

McapReader::McapReader(const fs::path& file) : file_(file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) fail(file, "no such MCAP file");
  size_ = fs::file_size(file, ec);
  in_.open(file, std::ios::binary);
  if (!in_ || ec) fail(file, "cannot open");
  const auto magic = bytes_at(0, std::min<std::uint64_t>(size_, 8));
  if (magic.size() < 8 || std::memcmp(magic.data(), kMagic, 8) != 0) fail(file, "not an MCAP file (no MCAP magic at its start)");
}

std::vector<std::uint8_t> McapReader::bytes_at(std::uint64_t at, std::uint64_t n) const {
  if (at > size_ || n > size_ - at) {
    fail(file_, "truncated: " + std::to_string(n) + " bytes at byte " + std::to_string(at) + " lie past its end (" +
                    std::to_string(size_) + " bytes)");
  }
  std::vector<std::uint8_t> out(n);
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(at));
  in_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
  if (!in_) fail(file_, "read failed at byte " + std::to_string(at));
  return out;
}

McapReader::Record McapReader::next_record(std::uint64_t at) const {
  if (size_ - at < kRecordPrefix) fail(file_, "truncated: a record at byte " + std::to_string(at) + " has no room for its length");
  const auto prefix = bytes_at(at, kRecordPrefix);
  std::uint64_t length;
  std::memcpy(&length, prefix.data() + 1, 8);
  if (length > size_ - at - kRecordPrefix) {
    fail(file_, "truncated: the record at byte " + std::to_string(at) + " (opcode " + std::to_string(prefix[0]) +
                    ") claims " + std::to_string(length) + " bytes, " + std::to_string(size_ - at - kRecordPrefix) + " are left");
  }
  if (prefix[0] == 0) fail(file_, "corrupt: opcode 0 at byte " + std::to_string(at));
  return {prefix[0], at, at + kRecordPrefix, length};
}

void McapReader::take_schema_or_channel(std::uint8_t opcode, const std::uint8_t* p, std::size_t n) {
  Fields f(p, n, file_.string());
  if (opcode == kSchema) {
    const auto id = f.num<std::uint16_t>();
    std::string name = f.string();
    schemas_[id] = {name, f.string()};
    return;
  }
  McapChannel c;
  c.id = f.num<std::uint16_t>();
  const auto schema = f.num<std::uint16_t>();
  c.topic = f.string();
  c.message_encoding = f.string();
  if (auto s = schemas_.find(schema); s != schemas_.end()) {
    c.schema_name = s->second.first;
    c.schema_encoding = s->second.second;
  }
  channels_[c.id] = c;
}

// The chunk's records, decompressed and checked against its size and CRC.
std::vector<std::uint8_t> McapReader::chunk_records(std::uint64_t chunk) const {
  const Record r = next_record(chunk);
  const auto content = bytes_at(r.content, r.length);
  const std::string what = file_.string() + ": chunk at byte " + std::to_string(chunk);
  Fields f(content.data(), content.size(), what);
  f.num<std::uint64_t>();  // message start and end times
  f.num<std::uint64_t>();
  const auto uncompressed = f.num<std::uint64_t>();
  const auto crc = f.num<std::uint32_t>();
  const std::string compression = f.string();
  const auto compressed = f.num<std::uint64_t>();
  const std::uint8_t* data = f.take(compressed);
  if (compression != "" && (uncompressed > kMaxDecompressedBytes ||
                            uncompressed > std::max<std::uint64_t>(65536, compressed * kMaxChunkExpansion))) {
    throw Error(what + ": claims " + std::to_string(uncompressed) + " bytes from " + std::to_string(compressed) +
                " compressed (more than " + std::to_string(kMaxChunkExpansion) + "x or the 256 MiB limit of one chunk: corrupt)");
  }
  std::vector<std::uint8_t> out;
  if (compression.empty()) {
    if (compressed != uncompressed) throw Error(what + ": uncompressed, but its sizes differ (corrupt)");
    out.assign(data, data + compressed);
  } else if (compression == "zstd") {
    out = unzstd_frame(data, compressed, uncompressed, kMaxChunkExpansion, what);
  } else if (compression == "lz4") {
    out = unlz4(data, compressed, uncompressed, what);
  } else {
    throw Error(what + ": unknown compression '" + compression + "' (MCAP readers know zstd and lz4)");
  }
  if (crc != 0 && crc32(0L, out.data(), static_cast<uInt>(out.size())) != crc) {
    throw Error(what + ": CRC mismatch (corrupt chunk)");
  }
  return out;
}

void McapReader::inner_records(const std::vector<std::uint8_t>& records, std::uint64_t chunk,
                               const std::set<std::string>& topics, const OnMessage& on_message) {
  const std::string what = file_.string() + ": chunk at byte " + std::to_string(chunk);
  for (std::size_t at = 0; at < records.size();) {
    Fields prefix(records.data() + at, records.size() - at, what);
    const auto opcode = prefix.num<std::uint8_t>();
    const auto length = prefix.num<std::uint64_t>();
    const std::uint8_t* p = prefix.take(length);
    if (opcode == kSchema || opcode == kChannel) take_schema_or_channel(opcode, p, length);
    if (opcode == kMessage) {
      Fields f(p, length, what);
      McapMessageRef m;
      m.channel = f.num<std::uint16_t>();
      f.num<std::uint32_t>();
      m.log_time = f.num<std::uint64_t>();
      f.num<std::uint64_t>();
      std::size_t n;
      const std::uint8_t* data = f.rest(n);
      auto c = channels_.find(m.channel);
      if (c == channels_.end()) throw Error(what + ": a message on channel " + std::to_string(m.channel) + " before its Channel record");
      if (topics.count(c->second.topic)) {
        m.chunk = chunk;
        m.offset = static_cast<std::uint64_t>(data - records.data());
        m.size = n;
        on_message(c->second, m, data, n);
      }
    }
    at += kRecordPrefix + length;
  }
}

void McapReader::scan(const std::set<std::string>& topics, const OnMessage& on_message) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::uint64_t at = 8;;) {
    const Record r = next_record(at);
    if (r.opcode == kDataEnd || r.opcode == kFooter) return;
    if (r.opcode == kChunk) {
      auto records = chunk_records(r.start);
      inner_records(records, r.start, topics, on_message);
      cached_chunk_ = r.start;
      cached_records_ = std::move(records);
    } else if (r.opcode == kSchema || r.opcode == kChannel || r.opcode == kMessage) {
      // Outside chunks: the same records, read as a chunk of one.
      auto bytes = bytes_at(r.start, kRecordPrefix + r.length);
      std::vector<std::uint8_t> one(bytes.begin(), bytes.end());
      inner_records(one, McapMessageRef::kNoChunk, topics, [&](const McapChannel& c, McapMessageRef m, const std::uint8_t* d,
                                                               std::size_t n) {
        m.offset += r.start;  // a file offset now
        on_message(c, m, d, n);
      });
    }
    at = r.content + r.length;
    if (at == size_) fail(file_, "truncated: it ends after byte " + std::to_string(at) + " without a Data End or Footer record");
  }
}

std::vector<std::uint8_t> McapReader::read(const McapMessageRef& m) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (m.chunk == McapMessageRef::kNoChunk) return bytes_at(m.offset, m.size);
  if (cached_chunk_ != m.chunk) {  // scans are read in order: one chunk decompressed at a time
    cached_records_ = chunk_records(m.chunk);
    cached_chunk_ = m.chunk;
  }
  if (m.offset > cached_records_.size() || m.size > cached_records_.size() - m.offset) {
    fail(file_, "a message lies outside its chunk (the file changed since it was opened?)");
  }
  const auto* p = cached_records_.data() + m.offset;
  return std::vector<std::uint8_t>(p, p + m.size);
}

}  // namespace cleanmap
