#include "io/zstd_frame.hpp"

#include <zstd.h>

#include <algorithm>

#include "io/error.hpp"

namespace cleanmap {

std::vector<std::uint8_t> unzstd_frame(const std::uint8_t* src, std::size_t n, std::uint64_t want,
                                       std::uint64_t max_expansion, const std::string& what) {
  const std::size_t frame = ZSTD_findFrameCompressedSize(src, n);
  if (ZSTD_isError(frame)) throw Error(what + ": not a zstd frame (" + ZSTD_getErrorName(frame) + ")");
  if (frame != n) {
    throw Error(what + ": " + std::to_string(n - frame) + " bytes after its zstd frame of " + std::to_string(frame) +
                " (padded or corrupt)");
  }
  const auto size = ZSTD_getFrameContentSize(src, n);
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN) {
    throw Error(what + ": the zstd frame states no content size (corrupt)");
  }
  if (want != 0 && size != want) {
    throw Error(what + ": its zstd frame holds " + std::to_string(size) + " bytes, the record says " + std::to_string(want));
  }
  if (size > kMaxDecompressedBytes || size > std::max<std::uint64_t>(65536, n * max_expansion)) {
    throw Error(what + ": claims " + std::to_string(size) + " bytes from " + std::to_string(n) +
                " compressed (beyond " + std::to_string(max_expansion) + "x or the 256 MiB limit of one record: corrupt)");
  }
  std::vector<std::uint8_t> out(size);
  const std::size_t got = ZSTD_decompress(out.data(), out.size(), src, n);
  if (ZSTD_isError(got)) throw Error(what + ": zstd: " + ZSTD_getErrorName(got) + " (truncated or corrupt)");
  if (got != size) throw Error(what + ": zstd gave " + std::to_string(got) + " bytes, its frame says " + std::to_string(size));
  return out;
}

}  // namespace cleanmap
