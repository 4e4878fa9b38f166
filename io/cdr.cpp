#include "io/cdr.hpp"

#include <algorithm>
#include <cstring>

#include "io/error.hpp"

namespace cleanmap {

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::string what)
    : data_(data), size_(size), what_(std::move(what)) {
  if (size < 4) fail_here("shorter than the 4-byte CDR encapsulation header");
  if (data[0] != 0 || data[1] > 1) {
    fail_here("not plain CDR (encapsulation " + std::to_string(data[0]) + " " + std::to_string(data[1]) +
              "; expected 0 1 little-endian or 0 0 big-endian)");
  }
  big_endian_ = data[1] == 0;
}

void CdrReader::fail_here(const std::string& problem) const {
  throw Error(what_ + ": " + problem + " (at byte " + std::to_string(pos_) + " of " + std::to_string(size_) + ")");
}

void CdrReader::align(std::size_t n) {
  const std::size_t rel = pos_ - 4;
  const std::size_t padded = pos_ + (n - rel % n) % n;
  if (padded > size_) fail_here("ends inside its padding");
  pos_ = padded;
}

const std::uint8_t* CdrReader::take(std::size_t n) {
  if (n > size_ - pos_) fail_here("ends early (" + std::to_string(n) + " more bytes wanted)");
  const std::uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

std::uint8_t CdrReader::u8() { return *take(1); }

std::uint32_t CdrReader::u32() {
  align(4);
  std::uint8_t b[4];
  std::memcpy(b, take(4), 4);
  if (big_endian_) std::reverse(b, b + 4);
  std::uint32_t v;
  std::memcpy(&v, b, 4);
  return v;
}

double CdrReader::f64() {
  align(8);
  std::uint8_t b[8];
  std::memcpy(b, take(8), 8);
  if (big_endian_) std::reverse(b, b + 8);
  double v;
  std::memcpy(&v, b, 8);
  return v;
}

std::string CdrReader::string() {
  const std::uint32_t n = u32();
  if (n > remaining()) fail_here("a string of " + std::to_string(n) + " bytes runs past the end");
  const std::uint8_t* p = take(n);
  std::size_t len = n;
  if (len > 0 && p[len - 1] == 0) --len;  // the terminating NUL
  return std::string(reinterpret_cast<const char*>(p), len);
}

std::uint32_t CdrReader::count(std::size_t min_element_bytes) {
  const std::uint32_t n = u32();
  if (min_element_bytes > 0 && n > remaining() / min_element_bytes) {
    fail_here("a sequence of " + std::to_string(n) + " elements cannot fit in the " +
              std::to_string(remaining()) + " bytes left");
  }
  return n;
}

const std::uint8_t* CdrReader::bytes(std::size_t& size) {
  size = count(1);
  return take(size);
}

CdrWriter::CdrWriter(bool big_endian) : out_{0, static_cast<std::uint8_t>(big_endian ? 0 : 1), 0, 0},
                                        big_endian_(big_endian) {}

void CdrWriter::align(std::size_t n) {
  while ((out_.size() - 4) % n != 0) out_.push_back(0);
}

void CdrWriter::put(const void* value, std::size_t n) {
  std::uint8_t b[8];
  std::memcpy(b, value, n);
  if (big_endian_) std::reverse(b, b + n);
  out_.insert(out_.end(), b, b + n);
}

void CdrWriter::u8(std::uint8_t v) { out_.push_back(v); }

void CdrWriter::u32(std::uint32_t v) {
  align(4);
  put(&v, 4);
}

void CdrWriter::f64(double v) {
  align(8);
  put(&v, 8);
}

void CdrWriter::string(const std::string& s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  out_.insert(out_.end(), s.begin(), s.end());
  out_.push_back(0);
}

void CdrWriter::bytes(const std::uint8_t* data, std::size_t size) {
  u32(static_cast<std::uint32_t>(size));
  out_.insert(out_.end(), data, data + size);
}

}  // namespace cleanmap
