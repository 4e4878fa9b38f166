#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cleanmap {

// A stated limit on what one compressed record (an MCAP chunk, a rosbag2 message) may expand
// to: 256 MiB. A 128-beam x 2048 lidar sweep of 48-byte points is 12.6 MB; a 16-bit 1280 x 720
// depth image 1.8 MB.
inline constexpr std::uint64_t kMaxDecompressedBytes = std::uint64_t{256} << 20;

// One zstd frame `src[0, n)` decompressed to exactly `want` bytes (0: the frame's own content
// size), or an Error naming `what`. Checked before anything is allocated: the frame spans all n
// bytes (a real 48 KB frame padded with 1.5 MB of junk had passed a 1000x expansion rule and
// expanded to 1.5 GB), its header states its content size, which equals `want` and is within
// `max_expansion` times n and kMaxDecompressedBytes.
std::vector<std::uint8_t> unzstd_frame(const std::uint8_t* src, std::size_t n, std::uint64_t want,
                                       std::uint64_t max_expansion, const std::string& what);

}  // namespace cleanmap
