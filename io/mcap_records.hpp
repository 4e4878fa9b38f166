#pragma once

// The byte-level pieces that the MCAP reader and writer share: opcodes, the magic, and
// little-endian fields read (bounds-checked) and appended.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/error.hpp"

namespace cleanmap::mcap {

inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
enum Opcode : std::uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kStatistics = 0x0B, kDataEnd = 0x0F
};
inline constexpr std::size_t kRecordPrefix = 9;  // opcode + uint64 length

// Reads fields of one record's content; running past its end is an Error naming `what`.
class Fields {
 public:
  Fields(const std::uint8_t* p, std::size_t n, std::string what) : p_(p), n_(n), what_(std::move(what)) {}
  template <typename T>
  T num() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));  // the format and this machine are little-endian
    return v;
  }
  std::string string() {
    const auto len = num<std::uint32_t>();
    const auto* s = take(len);
    return std::string(reinterpret_cast<const char*>(s), len);
  }
  void skip_string() { take(num<std::uint32_t>()); }
  const std::uint8_t* rest(std::size_t& n) {
    n = n_ - pos_;
    return take(n);
  }
  const std::uint8_t* take(std::uint64_t k) {
    if (k > n_ - pos_) {
      throw Error(what_ + ": truncated record (" + std::to_string(k) + " bytes wanted, " + std::to_string(n_ - pos_) +
                  " left)");
    }
    const auto* q = p_ + pos_;
    pos_ += static_cast<std::size_t>(k);
    return q;
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_, pos_ = 0;
  std::string what_;
};

template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), b, b + sizeof(T));
}

inline void put_string(std::vector<std::uint8_t>& out, const std::string& s) {
  put<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out.insert(out.end(), s.begin(), s.end());
}

}  // namespace cleanmap::mcap
