#include "io/pcd_file.hpp"

#include <pcl/io/lzf.h>

#include <cmath>
#include <cstring>
#include <string>

#include "io/error.hpp"
#include "io/file_bytes.hpp"

namespace cleanmap {
namespace {

constexpr std::size_t kMaxHeader = 64 * 1024;  // bytes; real headers are a few hundred
constexpr std::size_t kMaxFields = 1024;
// LZF encodes a back reference of up to 264 bytes in 3: no stream expands more than 88 times.
constexpr std::uint64_t kLzfMaxExpansion = 90;

struct Header {
  std::vector<std::string> names;
  std::vector<std::uint64_t> sizes, counts;
  std::vector<char> types;
  std::optional<std::uint64_t> width, height, points;
  std::optional<Eigen::Isometry3d> viewpoint;
  std::string data;
  std::size_t body = 0;  // offset of the first byte after the DATA line
  int lines = 0;         // header lines, DATA included
};

std::uint8_t type_code(char type, std::uint64_t size) {
  if (type == 'F') return size == 4 ? 7 : size == 8 ? 8 : 0;
  if (type == 'I') return size == 1 ? 1 : size == 2 ? 3 : size == 4 ? 5 : size == 8 ? 9 : 0;
  if (type == 'U') return size == 1 ? 2 : size == 2 ? 4 : size == 4 ? 6 : size == 8 ? 10 : 0;
  return 0;
}

std::vector<std::uint64_t> counts_of(const std::filesystem::path& file, const std::string& key,
                                     const std::vector<std::string_view>& words, std::uint64_t max) {
  std::vector<std::uint64_t> out;
  for (std::size_t k = 1; k < words.size(); ++k) {
    const auto v = parse_count(words[k], max);
    if (!v && parse_count(words[k], UINT64_MAX)) {
      fail(file, key + " " + printable(words[k]) + " is more than a file of " + std::to_string(max) +
                     " bytes can hold (truncated, or a lying header)");
    }
    if (!v) fail(file, key + ": '" + printable(words[k]) + "' is not a count");
    out.push_back(*v);
  }
  return out;
}

Eigen::Isometry3d viewpoint_of(const std::filesystem::path& file, const std::vector<std::string_view>& w) {
  double v[7];
  for (int k = 0; k < 7; ++k) {
    const auto x = w.size() == 8 ? parse_number(w[k + 1]) : std::nullopt;
    if (!x || !std::isfinite(*x)) fail(file, "VIEWPOINT must be 7 finite numbers (tx ty tz qw qx qy qz)");
    v[k] = *x;
  }
  const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  if (!(q.norm() > 1e-6)) fail(file, "VIEWPOINT quaternion has zero length");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return pose;
}

Header parse_header(const std::filesystem::path& file, std::string_view text) {
  Header h;
  std::size_t pos = 0;
  const std::string_view head = text.substr(0, kMaxHeader);
  int line_no = 0;
  while (auto line = next_line(head, pos)) {
    ++line_no;
    const auto w = split_words(*line);
    if (w.empty() || w[0].front() == '#') continue;
    const std::string key(w[0]);
    const std::uint64_t max = text.size();  // no count in a header can exceed the file's bytes
    if (key == "VERSION") continue;
    if (key == "FIELDS" || key == "COLUMNS") {
      if (w.size() < 2 || w.size() - 1 > kMaxFields) fail(file, "FIELDS must list 1-1024 fields");
      for (std::size_t k = 1; k < w.size(); ++k) h.names.emplace_back(w[k]);
    } else if (key == "SIZE") {
      h.sizes = counts_of(file, key, w, UINT64_MAX);  // TYPE and SIZE are checked together below
    } else if (key == "TYPE") {
      for (std::size_t k = 1; k < w.size(); ++k) h.types.push_back(w[k].size() == 1 ? w[k][0] : '?');
    } else if (key == "COUNT") {
      h.counts = counts_of(file, key, w, max);
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      const auto v = counts_of(file, key, w, max);
      if (v.size() != 1) fail(file, key + " must be one count");
      (key == "WIDTH" ? h.width : key == "HEIGHT" ? h.height : h.points) = v[0];
    } else if (key == "VIEWPOINT") {
      h.viewpoint = viewpoint_of(file, w);
    } else if (key == "DATA") {
      h.data = w.size() == 2 ? std::string(w[1]) : "";
      h.body = pos;
      h.lines = line_no;
      if (h.counts.empty()) h.counts.assign(h.names.size(), 1);  // COUNT is optional (v0.5)
      return h;
    } else {
      fail(file, "header line " + std::to_string(line_no) + ": unknown entry '" + printable(key) +
                     "' (not a PCD file?)");
    }
  }
  fail(file, text.empty() ? "empty file (0 bytes)" : "no DATA line in the header (not a PCD file?)");
}

// Field layout from the header; the point step as the fields' total.
CloudRecords layout(const std::filesystem::path& file, const Header& h, std::size_t file_size) {
  const std::size_t n = h.names.size();
  if (n == 0) fail(file, "header has no FIELDS line");
  const auto& counts = h.counts;
  if (h.sizes.size() != n || h.types.size() != n || counts.size() != n) {
    fail(file, "FIELDS, SIZE, TYPE and COUNT list different numbers of entries");
  }
  CloudRecords r;
  std::uint64_t step = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t code = type_code(h.types[k], h.sizes[k]);
    if (code == 0) {
      fail(file, "field '" + printable(h.names[k]) + "': TYPE " + std::string(1, h.types[k]) + " with SIZE " +
                     std::to_string(h.sizes[k]) + " is not a PCD type");
    }
    if (counts[k] == 0) fail(file, "field '" + printable(h.names[k]) + "' has COUNT 0");
    r.fields.push_back({h.names[k], static_cast<std::uint32_t>(step), code});
    step += h.sizes[k] * counts[k];
    if (step > file_size) fail(file, "a point of the header's fields is larger than the whole file");
  }
  r.point_step = static_cast<std::uint32_t>(step);
  const std::uint64_t width = h.width.value_or(0), height = h.height.value_or(1);
  if (!h.width && !h.points) fail(file, "header has neither WIDTH nor POINTS");
  if (height != 0 && width > file_size / height) fail(file, "WIDTH x HEIGHT exceeds what the file can hold");
  r.points = h.points.value_or(width * height);
  if (h.width && r.points != width * height) {
    fail(file, "POINTS " + std::to_string(r.points) + " differs from WIDTH x HEIGHT " + std::to_string(width * height));
  }
  if (h.viewpoint && !h.viewpoint->isApprox(Eigen::Isometry3d::Identity())) r.viewpoint = h.viewpoint;
  return r;
}

void read_binary(const std::filesystem::path& file, std::string_view body, CloudRecords& r) {
  if (body.size() / r.point_step < r.points) {
    fail(file, "truncated: binary data holds " + std::to_string(body.size()) + " bytes, " +
                   std::to_string(r.points) + " points of " + std::to_string(r.point_step) + " bytes need " +
                   std::to_string(r.points * r.point_step));
  }
  r.data.assign(body.begin(), body.begin() + static_cast<std::ptrdiff_t>(r.points * r.point_step));
}

// binary_compressed: two uint32 (compressed, uncompressed size), then LZF of the fields one
// after the other (all x, then all y, ...), turned back into records here.
void read_compressed(const std::filesystem::path& file, std::string_view body, const Header& h,
                     CloudRecords& r) {
  std::uint32_t sizes[2] = {0, 0};
  if (body.size() < 8) fail(file, "truncated: binary_compressed data has no size words");
  std::memcpy(sizes, body.data(), 8);
  const std::uint64_t packed = sizes[0], unpacked = sizes[1], need = r.points * std::uint64_t{r.point_step};
  if (packed > body.size() - 8) {
    fail(file, "truncated: compressed data holds " + std::to_string(body.size() - 8) + " bytes, its size word says " +
                   std::to_string(packed));
  }
  if (unpacked != need) {
    fail(file, "compressed data unpacks to " + std::to_string(unpacked) + " bytes, " + std::to_string(r.points) +
                   " points need " + std::to_string(need));
  }
  if (need == 0) return;
  if (unpacked > kLzfMaxExpansion * packed) {
    fail(file, "compressed size " + std::to_string(packed) + " cannot unpack to " + std::to_string(unpacked) + " bytes");
  }
  std::vector<std::uint8_t> fields(need);
  const unsigned got = pcl::lzfDecompress(body.data() + 8, static_cast<unsigned>(packed), fields.data(),
                                          static_cast<unsigned>(need));
  if (got != need) fail(file, "compressed data is corrupt (LZF unpacked " + std::to_string(got) + " bytes)");
  r.data.resize(need);
  std::size_t from = 0;
  for (std::size_t k = 0; k < r.fields.size(); ++k) {
    const std::size_t width = h.sizes[k] * h.counts[k];
    for (std::size_t i = 0; i < r.points; ++i) {
      std::memcpy(r.data.data() + i * r.point_step + r.fields[k].offset, fields.data() + from + i * width, width);
    }
    from += width * r.points;
  }
}

void read_ascii(const std::filesystem::path& file, std::string_view body, const Header& h, CloudRecords& r) {
  std::size_t words = 0;
  for (std::size_t k = 0; k < r.fields.size(); ++k) words += h.counts[k];
  // Each value takes a character and a separator at least (the very last needs no newline).
  const std::size_t most = (body.size() + 1) / (2 * words);
  if (r.points > most) {
    fail(file, "claims " + std::to_string(r.points) + " points; its ascii data (" + std::to_string(body.size()) +
                   " bytes) holds at most " + std::to_string(most));
  }
  r.data.assign(r.points * r.point_step, 0);
  std::size_t pos = 0, row = 0;
  for (std::size_t line_no = h.lines + 1; row < r.points; ++line_no) {
    const auto line = next_line(body, pos);
    if (!line) fail(file, "truncated: " + std::to_string(row) + " of " + std::to_string(r.points) + " points");
    const auto w = split_words(*line);
    if (w.empty()) continue;
    if (w.size() != words) {
      fail(file, "line " + std::to_string(line_no) + ": " + std::to_string(w.size()) + " values, the fields need " +
                     std::to_string(words));
    }
    std::size_t word = 0;
    for (std::size_t k = 0; k < r.fields.size(); ++k) {
      for (std::size_t c = 0; c < h.counts[k]; ++c, ++word) {
        const auto v = parse_number(w[word]);
        std::uint8_t* out = r.data.data() + row * r.point_step + r.fields[k].offset + c * h.sizes[k];
        // PCL writes a packed float colour as the integer of its bits.
        const bool colour = (r.fields[k].name == "rgb" || r.fields[k].name == "rgba") && h.sizes[k] == 4;
        if (!v || !((colour && store_value(*v, 6, out)) || store_value(*v, r.fields[k].datatype, out))) {
          fail(file, "line " + std::to_string(line_no) + ": '" + printable(w[word]) +
                         "' is not a value of field '" + r.fields[k].name + "'");
        }
      }
    }
    ++row;
  }
}

}  // namespace

CloudRecords read_pcd(const std::filesystem::path& file) {
  const auto bytes = read_file_bytes(file);
  return parse_pcd(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file);
}

CloudRecords parse_pcd(std::string_view text, const std::filesystem::path& file) {
  const Header h = parse_header(file, text);
  CloudRecords r = layout(file, h, text.size());
  const std::string_view body = text.substr(h.body);
  if (h.data == "binary") {
    read_binary(file, body, r);
  } else if (h.data == "binary_compressed") {
    read_compressed(file, body, h, r);
  } else if (h.data == "ascii") {
    read_ascii(file, body, h, r);
  } else {
    fail(file, "DATA must be ascii, binary or binary_compressed");
  }
  return r;
}

}  // namespace cleanmap
