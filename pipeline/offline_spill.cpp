#include "pipeline/offline_spill.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap::pipeline {
namespace {

// 3: the payload compressed (zstd), each array stored as its elements' byte planes.
// 4: with ScoredScan::on_moving_track.
constexpr char kMagic[8] = {'C', 'M', 'S', 'P', 'I', 'L', 'L', '4'};
// A fast level: an offline run costs 1.88x the online one's CPU on the synthetic stream (1.38x
// on the Pandar64 street), against a bound of 2x. On the
// synthetic stream (bench/compare_cpu.sh against the build without compression) level 1 cost
// 4.6 % of the run's CPU and -3 3.7 %, for spills 4-10 % larger (14.8 -> 15.7 bytes a point
// on the Pandar64 street, 13.0 -> 14.3 on SemanticKITTI 04, 12.3 -> 12.8 on the synthetic
// street); lz4 was faster again on a Pandar64 scan's planes but left them 1.68x smaller where
// zstd -3 left them 1.98x.
constexpr int kLevel = -3;
// Bytes not set to zero first: a spill's buffers are written whole before they are read, and
// zero-filling them (std::string, std::vector) cost a memset each.
struct Bytes {
  std::unique_ptr<unsigned char[]> data;
  std::size_t size = 0, capacity = 0;
  explicit Bytes(std::size_t reserve = 0) : data(new unsigned char[reserve]), capacity(reserve) {}
  void reserve(std::size_t n) {
    if (n <= capacity) return;
    std::unique_ptr<unsigned char[]> more(new unsigned char[n]);
    std::memcpy(more.get(), data.get(), size);
    data = std::move(more);
    capacity = n;
  }
  unsigned char* grow(std::size_t n) {  // n more bytes at the end; returns where they start
    if (size + n > capacity) reserve(std::max(size + n, 2 * capacity));
    size += n;
    return data.get() + size - n;
  }
};

// The payload before compression. Arrays are written as byte planes (every element's first
// byte, then every second byte, ...): a point cloud's coordinates share their sign and exponent
// bytes, and an input index's high bytes, which then compress away (x y z 12 -> 9.2 bytes a
// point, input index 4 -> 0.01, per-point time 4 -> 0.1, on a Pandar64 scan).
struct Writer {
  Bytes bytes;
  template <typename T>
  void put(const T& v) {
    std::memcpy(bytes.grow(sizeof v), &v, sizeof v);
  }
  template <typename T>
  void put_array(const T* data, std::size_t n) {
    put(static_cast<std::uint64_t>(n));
    const auto* in = reinterpret_cast<const unsigned char*>(data);
    unsigned char* out = bytes.grow(n * sizeof(T));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t b = 0; b < sizeof(T); ++b) out[b * n + i] = in[i * sizeof(T) + b];
    }
  }
};

struct Reader {
  const std::filesystem::path& file;
  const Bytes& bytes;
  std::size_t at = 0;
  std::size_t left() const { return bytes.size - at; }
  template <typename T>
  T get() {
    T v{};
    if (left() < sizeof v) fail(file, "truncated spill file");
    std::memcpy(&v, bytes.data.get() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  // The element count of the next array, checked against what the payload still holds.
  std::size_t count(std::size_t element) {
    const auto n = get<std::uint64_t>();
    if (n > left() / element) fail(file, "spill file claims more data than it holds");
    return static_cast<std::size_t>(n);
  }
  template <typename T>
  void get_array(T* data, std::size_t n) {
    if (left() < n * sizeof(T)) fail(file, "truncated spill file");
    auto* out = reinterpret_cast<unsigned char*>(data);
    const unsigned char* in = bytes.data.get() + at;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t b = 0; b < sizeof(T); ++b) out[i * sizeof(T) + b] = in[b * n + i];
    }
    at += n * sizeof(T);
  }
};

Bytes compress(const Bytes& raw) {
  thread_local std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> ctx(ZSTD_createCCtx(),
                                                                        &ZSTD_freeCCtx);
  if (!ctx) throw Error("zstd: cannot create a compression context");
  Bytes out(ZSTD_compressBound(raw.size));
  const std::size_t n =
      ZSTD_compressCCtx(ctx.get(), out.data.get(), out.capacity, raw.data.get(), raw.size, kLevel);
  if (ZSTD_isError(n)) throw Error(std::string("zstd: ") + ZSTD_getErrorName(n));
  out.size = n;
  return out;
}

// The frame decompressed as it comes, so what is allocated is what the frame really holds,
// never what a header claims (zstd shrinks a run of one byte 30000-fold): at first what a spill
// could hold at 16 times its size (they shrink 2-3 fold), more only as the frame proves it.
Bytes decompress(const std::filesystem::path& file, const Bytes& frame, std::uint64_t raw_size) {
  thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(),
                                                                        &ZSTD_freeDCtx);
  if (!ctx) throw Error("zstd: cannot create a decompression context");
  ZSTD_DCtx_reset(ctx.get(), ZSTD_reset_session_only);
  Bytes raw(static_cast<std::size_t>(std::min<std::uint64_t>(raw_size, 16 * frame.size + 4096)));
  ZSTD_inBuffer in{frame.data.get(), frame.size, 0};
  while (true) {
    // Full: twice as much room, but never past one byte more than the header says.
    if (raw.size == raw.capacity)
      raw.reserve(raw.capacity + std::min<std::size_t>(raw.capacity + 1, raw_size - raw.size + 1));
    ZSTD_outBuffer out{raw.data.get(), raw.capacity, raw.size};
    const std::size_t rc = ZSTD_decompressStream(ctx.get(), &out, &in);
    if (ZSTD_isError(rc))
      fail(file, "corrupt spill file (" + std::string(ZSTD_getErrorName(rc)) + ")");
    const bool full = out.pos == out.size;
    raw.size = out.pos;
    if (rc == 0) break;  // the frame is complete
    if (in.pos == in.size && !full)
      fail(file, "truncated spill file");  // wants input that is not there
    if (raw.size > raw_size) break;
  }
  if (raw.size != raw_size || in.pos != in.size)
    fail(file, "corrupt spill file (its size does not match its header)");
  return raw;
}

// The payload of a spill file: its header checked, its frame decompressed.
Bytes payload(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read spill file");
  std::ifstream f(file, std::ios::binary);
  if (!f) fail(file, "cannot read spill file");
  char magic[8] = {};
  std::uint64_t raw_size = 0;
  if (size < sizeof magic + sizeof raw_size || !f.read(magic, sizeof magic) ||
      !f.read(reinterpret_cast<char*>(&raw_size), sizeof raw_size)) {
    fail(file, "truncated spill file");
  }
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) fail(file, "not a cleanmap spill file");
  Bytes frame(static_cast<std::size_t>(size - sizeof magic - sizeof raw_size));
  frame.size = frame.capacity;
  if (!f.read(reinterpret_cast<char*>(frame.data.get()),
              static_cast<std::streamsize>(frame.size))) {
    fail(file, "truncated spill file");
  }
  const auto content = ZSTD_getFrameContentSize(frame.data.get(), frame.size);
  if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN ||
      content != raw_size) {
    fail(file, "corrupt spill file (its compressed frame does not match its header)");
  }
  return decompress(file, frame, raw_size);
}

}  // namespace

std::size_t write_spill(const std::filesystem::path& file, const ScoredScan& r,
                        const std::vector<std::uint32_t>& labels) {
  const Scan& s = r.scan;
  Writer w{Bytes(40 * static_cast<std::size_t>(s.points.cols()) + 4096)};  // at most 33 a point
  w.put(static_cast<std::uint64_t>(r.index));
  w.put(s.stamp);
  const Eigen::Matrix4d pose = s.pose ? s.pose->matrix() : Eigen::Matrix4d::Identity();
  w.put(static_cast<std::uint8_t>(s.pose.has_value()));
  for (int k = 0; k < 16; ++k) w.put(pose.data()[k]);
  w.put_array(s.name.data(), s.name.size());
  w.put(static_cast<std::uint64_t>(s.input_size));
  w.put_array(s.points.data(), static_cast<std::size_t>(s.points.size()));
  w.put_array(s.intensity.data(), static_cast<std::size_t>(s.intensity.size()));
  w.put_array(s.time.data(), static_cast<std::size_t>(s.time.size()));
  w.put_array(s.input_index.data(), s.input_index.size());
  w.put_array(r.score.data(), r.score.size());
  w.put_array(r.dynamic.data(), r.dynamic.size());
  w.put_array(r.on_moving_track.data(), r.on_moving_track.size());
  w.put_array(labels.data(), labels.size());
  for (const auto v : {r.downsampled, r.scored_downsampled, r.dynamic_before_completion, r.dynamic_downsampled,
                       r.tracked_points}) {
    w.put(static_cast<std::uint64_t>(v));
  }
  w.put(static_cast<std::int32_t>(r.scans_before));
  w.put(static_cast<std::int32_t>(r.scans_after));
  w.put(r.voxel_size);
  w.put(r.seconds);
  const Bytes frame = compress(w.bytes);
  std::ofstream f(file, std::ios::binary | std::ios::trunc);
  if (!f) fail(file, "cannot write");
  f.write(kMagic, sizeof kMagic);
  const auto raw_size = static_cast<std::uint64_t>(w.bytes.size);
  f.write(reinterpret_cast<const char*>(&raw_size), sizeof raw_size);
  f.write(reinterpret_cast<const char*>(frame.data.get()),
          static_cast<std::streamsize>(frame.size));
  close_checked(f, file);
  return sizeof kMagic + sizeof raw_size + frame.size;
}

std::string spill_space_problem(const std::filesystem::path& dir, std::size_t bytes,
                                std::size_t done, std::size_t left, std::uintmax_t available) {
  if (done == 0 || left == 0) return {};
  const double per_scan = static_cast<double>(bytes) / static_cast<double>(done);
  const double needed = per_scan * static_cast<double>(left);
  if (needed <= static_cast<double>(available)) return {};
  auto size = [](double bytes) {
    char text[32];
    if (bytes >= 1e9)
      std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    else
      std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
    return std::string(text);
  };
  const std::string line =
      "the offline run's spills need about " + size(needed) + " more for " + std::to_string(left) +
      " scans still to come (" + size(per_scan) + " a scan so far), " +
      size(static_cast<double>(available)) +
      " free: free space there, write --out to a larger disk, or run with --online";
  return dir.string() + ": " + line;
}

void check_spill_space(const std::filesystem::path& dir, std::size_t bytes, std::size_t done,
                       std::size_t left) {
  std::error_code ec;
  const auto space = std::filesystem::space(dir, ec);
  if (ec)
    return;  // not known (an unusual file system): the writes still fail clearly when it fills
  const auto problem = spill_space_problem(dir, bytes, done, left, space.available);
  if (!problem.empty()) throw Error(problem);
}

SpilledScan read_spill(const std::filesystem::path& file) {
  const Bytes raw = payload(file);
  Reader in{file, raw};
  SpilledScan out;
  ScoredScan& r = out.scored;
  Scan& s = r.scan;
  r.index = static_cast<std::size_t>(in.get<std::uint64_t>());
  s.stamp = in.get<double>();
  const bool has_pose = in.get<std::uint8_t>() != 0;
  Eigen::Matrix4d pose;
  for (int k = 0; k < 16; ++k) pose.data()[k] = in.get<double>();
  if (has_pose) s.pose = Eigen::Isometry3d(pose);
  s.name.resize(in.count(1));
  in.get_array(s.name.data(), s.name.size());
  s.input_size = static_cast<std::size_t>(in.get<std::uint64_t>());
  const auto n3 = in.count(sizeof(float));
  if (n3 % 3 != 0) fail(file, "point array is not x y z triples");
  s.points.resize(3, static_cast<Eigen::Index>(n3 / 3));
  in.get_array(s.points.data(), n3);
  const std::size_t n = n3 / 3;
  auto sized = [&](std::size_t got, const char* what) {
    if (got != 0 && got != n) fail(file, std::string(what) + ": " + std::to_string(got) + " values for " + std::to_string(n) + " points");
    return got;
  };
  s.intensity.resize(static_cast<Eigen::Index>(sized(in.count(sizeof(float)), "intensity")));
  in.get_array(s.intensity.data(), static_cast<std::size_t>(s.intensity.size()));
  s.time.resize(static_cast<Eigen::Index>(sized(in.count(sizeof(float)), "times")));
  in.get_array(s.time.data(), static_cast<std::size_t>(s.time.size()));
  s.input_index.resize(sized(in.count(sizeof(std::int32_t)), "input index"));
  in.get_array(s.input_index.data(), s.input_index.size());
  r.score.resize(sized(in.count(sizeof(float)), "scores"));
  in.get_array(r.score.data(), r.score.size());
  r.dynamic.resize(sized(in.count(1), "decisions"));
  in.get_array(r.dynamic.data(), r.dynamic.size());
  if (r.score.size() != n || r.dynamic.size() != n) fail(file, "scores or decisions missing");
  r.on_moving_track.resize(sized(in.count(1), "moving tracks"));
  in.get_array(r.on_moving_track.data(), r.on_moving_track.size());
  out.labels.resize(sized(in.count(sizeof(std::uint32_t)), "labels"));
  in.get_array(out.labels.data(), out.labels.size());
  for (std::size_t* v : {&r.downsampled, &r.scored_downsampled, &r.dynamic_before_completion, &r.dynamic_downsampled,
                         &r.tracked_points}) {
    *v = static_cast<std::size_t>(in.get<std::uint64_t>());
  }
  r.scans_before = in.get<std::int32_t>();
  r.scans_after = in.get<std::int32_t>();
  r.voxel_size = in.get<double>();
  r.seconds = in.get<double>();
  if (in.left() != 0) fail(file, "spill file holds more than one scan");
  return out;
}

}  // namespace cleanmap::pipeline
