#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cleanmap {

// OMG CDR as ROS 2 serialises messages (XCDR1, what rosbag2 stores): a 4-byte encapsulation
// header (0x00 0x01 little-endian, 0x00 0x00 big-endian, then two option bytes), then each
// primitive aligned to its own size (8 at most) counted from the end of that header; strings
// are a uint32 length including the terminating NUL, sequences a uint32 count.
//
// Reader and writer share the alignment rule, so a message written here reads back the same
// way a recorded one does. Every read is bounds-checked: past the end, or a length larger than
// the bytes left, is an Error naming `what` (the message being decoded), before any allocation.
class CdrReader {
 public:
  CdrReader(const std::uint8_t* data, std::size_t size, std::string what);

  bool big_endian() const { return big_endian_; }
  std::uint8_t u8();
  bool boolean() { return u8() != 0; }
  std::uint32_t u32();
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  double f64();
  std::string string();
  // A uint32 count of elements each at least `min_element_bytes` long, checked against what is left.
  std::uint32_t count(std::size_t min_element_bytes);
  // A uint8 sequence: the count, then a view of its bytes (valid while the input lives).
  const std::uint8_t* bytes(std::size_t& size);
  std::size_t remaining() const { return size_ - pos_; }

 private:
  void align(std::size_t n);
  const std::uint8_t* take(std::size_t n);
  [[noreturn]] void fail_here(const std::string& problem) const;

  const std::uint8_t* data_;
  std::size_t size_, pos_ = 4;  // positions count from the start; alignment from 4
  bool big_endian_ = false;
  std::string what_;
};

class CdrWriter {
 public:
  explicit CdrWriter(bool big_endian = false);

  void u8(std::uint8_t v);
  void boolean(bool v) { u8(v ? 1 : 0); }
  void u32(std::uint32_t v);
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v);
  void string(const std::string& s);
  void bytes(const std::uint8_t* data, std::size_t size);
  const std::vector<std::uint8_t>& data() const { return out_; }

 private:
  void align(std::size_t n);
  void put(const void* value, std::size_t n);

  std::vector<std::uint8_t> out_;
  bool big_endian_;
};

}  // namespace cleanmap
