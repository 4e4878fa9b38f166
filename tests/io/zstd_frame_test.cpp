// Compressed records are checked before anything is allocated (issue 45: a real 48 KB frame
// padded past the 1000x rule expanded to 1.5 GB; a message claiming 2.2 GB was believed).
#include "io/zstd_frame.hpp"

#include <zstd.h>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

std::vector<std::uint8_t> compressed(const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> out(ZSTD_compressBound(data.size()));
  out.resize(ZSTD_compress(out.data(), out.size(), data.data(), data.size(), 3));
  return out;
}

TEST(ZstdFrame, AFrameIsReadOnlyWhenItsSizesHold) {
  std::vector<std::uint8_t> data(200000);
  std::uint32_t lcg = 1;  // 4 random bits a byte: about 2x compressible
  for (auto& b : data) b = static_cast<std::uint8_t>((lcg = lcg * 1664525u + 1013904223u) >> 28);
  auto z = compressed(data);
  EXPECT_EQ(unzstd_frame(z.data(), z.size(), data.size(), 1000, "m"), data);
  EXPECT_EQ(unzstd_frame(z.data(), z.size(), 0, 1000, "m"), data);  // its own content size
  test::expect_error([&] { unzstd_frame(z.data(), z.size(), data.size() + 1, 1000, "m"); },
                     {"m: its zstd frame holds 200000 bytes, the record says 200001"});
  // Padded with junk so that its compressed size passes an expansion rule.
  auto padded = z;
  padded.resize(z.size() + 5000, 0xAB);
  test::expect_error([&] { unzstd_frame(padded.data(), padded.size(), 0, 1000, "chunk"); },
                     {"chunk: 5000 bytes after its zstd frame"});
  // 200 kB from about 100 kB is beyond 1x.
  test::expect_error([&] { unzstd_frame(z.data(), z.size(), 0, 1, "m"); }, {"beyond 1x"});
  // A 26-byte frame whose header claims 2.2 GB (one raw block of 10 bytes): refused by the
  // 256 MiB limit, whatever expansion the caller allows.
  std::vector<std::uint8_t> liar{0x28, 0xB5, 0x2F, 0xFD, 0xE0};
  const std::uint64_t claim = 2200000000ull;
  for (int b = 0; b < 8; ++b) liar.push_back(static_cast<std::uint8_t>(claim >> (8 * b)));
  liar.insert(liar.end(), {0x51, 0x00, 0x00});
  liar.insert(liar.end(), 10, 0x00);
  ASSERT_EQ(ZSTD_getFrameContentSize(liar.data(), liar.size()), claim);
  test::expect_error([&] { unzstd_frame(liar.data(), liar.size(), 0, 1000000000, "msg"); },
                     {"msg: claims 2200000000 bytes", "256 MiB limit"});
}

}  // namespace
}  // namespace cleanmap
