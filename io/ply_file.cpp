#include "io/ply_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "io/error.hpp"
#include "io/file_bytes.hpp"

namespace cleanmap {
namespace {

constexpr std::size_t kMaxHeader = 64 * 1024;  // bytes

enum class Format { kAscii, kLittle, kBig };

struct Property {
  std::string name;
  std::uint8_t type = 0;        // type code of the value (of each item, for a list)
  std::uint8_t count_type = 0;  // list length's type code; 0 = not a list
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  std::size_t body = 0;
  int lines = 0;
};

std::uint8_t ply_type(std::string_view t) {
  static const std::map<std::string_view, std::uint8_t> codes{
      {"char", 1}, {"int8", 1}, {"uchar", 2}, {"uint8", 2}, {"short", 3}, {"int16", 3},
      {"ushort", 4}, {"uint16", 4}, {"int", 5}, {"int32", 5}, {"uint", 6}, {"uint32", 6},
      {"float", 7}, {"float32", 7}, {"double", 8}, {"float64", 8}};
  const auto it = codes.find(t);
  return it == codes.end() ? 0 : it->second;
}

Header parse_header(const std::filesystem::path& file, std::string_view text) {
  if (text.empty()) fail(file, "empty file (0 bytes)");
  Header h;
  std::size_t pos = 0;
  const std::string_view head = text.substr(0, kMaxHeader);
  const auto first = next_line(head, pos);
  if (!first || *first != "ply") fail(file, "does not start with 'ply' (not a PLY file?)");
  h.lines = 1;
  bool format = false;
  while (auto line = next_line(head, pos)) {
    ++h.lines;
    const auto w = split_words(*line);
    const std::string at = "header line " + std::to_string(h.lines) + ": ";
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (!format) fail(file, "header has no format line");
      h.body = pos;
      return h;
    }
    if (w[0] == "format" && w.size() == 3) {
      if (w[1] == "ascii") h.format = Format::kAscii;
      else if (w[1] == "binary_little_endian") h.format = Format::kLittle;
      else if (w[1] == "binary_big_endian") h.format = Format::kBig;
      else fail(file, at + "unknown format '" + printable(w[1]) + "'");
      format = true;
    } else if (w[0] == "element" && w.size() == 3) {
      const auto n = parse_count(w[2], text.size());
      if (!n) fail(file, at + "element count '" + printable(w[2]) + "' exceeds what the file can hold");
      h.elements.push_back({std::string(w[1]), *n, {}});
    } else if (w[0] == "property" && !h.elements.empty()) {
      Property p;
      if (w.size() == 3) {
        p = {std::string(w[2]), ply_type(w[1]), 0};
      } else if (w.size() == 5 && w[1] == "list") {
        p = {std::string(w[4]), ply_type(w[3]), ply_type(w[2])};
        if (p.count_type == 0 || p.count_type >= 7) fail(file, at + "a list's length must have an integer type");
      }
      if (p.type == 0) fail(file, at + "unknown property '" + printable(*line, 60) + "'");
      h.elements.back().properties.push_back(p);
    } else {
      fail(file, at + "unknown entry '" + printable(*line) + "' (not a PLY file?)");
    }
  }
  fail(file, "no end_header line in the header (not a PLY file?)");
}

// Reads values of one element instance in turn, from ascii words or binary bytes.
struct Cursor {
  const std::filesystem::path& file;
  std::string_view body;
  Format format;
  std::size_t pos = 0;
  int line_no = 0;
  std::vector<std::string_view> words;
  std::size_t word = 0;

  void start_instance() {
    if (format != Format::kAscii) return;
    while (true) {
      const auto line = next_line(body, pos);
      if (!line) fail(file, "truncated: the body ends before the header's element counts");
      ++line_no;
      words = split_words(*line);
      word = 0;
      if (!words.empty()) return;
    }
  }
  void end_instance() const {
    if (format == Format::kAscii && word != words.size()) {
      fail(file, "line " + std::to_string(line_no) + ": " + std::to_string(words.size()) + " values, the properties need " +
                     std::to_string(word));
    }
  }
  // The next value as double; its little-endian bytes go to `raw` when given.
  double next(std::uint8_t type, std::uint8_t* raw = nullptr) {
    const std::uint32_t size = type_size(type);
    if (format == Format::kAscii) {
      const auto v = word < words.size() ? parse_number(words[word]) : std::nullopt;
      if (!v) {
        fail(file, "line " + std::to_string(line_no) + ": " +
                       (word < words.size() ? "'" + printable(words[word]) + "' is not a number"
                                            : "too few values"));
      }
      ++word;
      if (raw && !store_value(*v, type, raw)) fail(file, "line " + std::to_string(line_no) + ": value out of its type's range");
      return *v;
    }
    if (body.size() - pos < size) fail(file, "truncated: the binary body ends before the header's element counts");
    std::uint8_t bytes[8];
    std::memcpy(bytes, body.data() + pos, size);
    pos += size;
    if (format == Format::kBig) std::reverse(bytes, bytes + size);
    if (raw) std::memcpy(raw, bytes, size);
    return read_value(bytes, type);
  }
};

// Bytes an instance needs at least: binary fixed sizes (a list at least its length), ascii a
// character and a separator per value.
std::uint64_t min_instance_bytes(const Element& e, Format format) {
  std::uint64_t n = 0;
  for (const auto& p : e.properties) {
    n += format == Format::kAscii ? 2 : type_size(p.count_type ? p.count_type : p.type);
  }
  return n;
}

void skip_instance(Cursor& c, const Element& e) {
  c.start_instance();
  for (const auto& p : e.properties) {
    if (p.count_type == 0) {
      c.next(p.type);
      continue;
    }
    const double items = c.next(p.count_type);
    if (!(items >= 0) || items > static_cast<double>(c.body.size())) fail(c.file, "a list is longer than the file");
    for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(items); ++k) c.next(p.type);
  }
  c.end_instance();
}

std::optional<Eigen::Isometry3d> camera_pose(const std::filesystem::path& file, const std::map<std::string, double>& v) {
  auto get = [&](const char* name) {
    const auto it = v.find(name);
    return it == v.end() ? std::nan("") : it->second;
  };
  if (!v.count("view_px")) return std::nullopt;
  Eigen::Matrix3d r;
  const char* axes[3][3] = {{"x_axisx", "x_axisy", "x_axisz"}, {"y_axisx", "y_axisy", "y_axisz"}, {"z_axisx", "z_axisy", "z_axisz"}};
  // As PCL reads it: each axis is a row of the rotation.
  for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) r(i, j) = get(axes[i][j]);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(get("view_px"), get("view_py"), get("view_pz"));
  if (!r.allFinite() || !pose.translation().allFinite() || std::abs(r.determinant() - 1.0) > 1e-3) {
    fail(file, "camera element is not a finite pose with a rotation");
  }
  pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  if (pose.isApprox(Eigen::Isometry3d::Identity())) return std::nullopt;
  return pose;
}

CloudRecords read_vertices(Cursor& c, const Element& e) {
  CloudRecords r;
  std::uint32_t step = 0;
  for (const auto& p : e.properties) {
    if (p.count_type != 0) fail(c.file, "vertex property '" + p.name + "' is a list");
    r.fields.push_back({p.name, step, p.type});
    step += type_size(p.type);
  }
  r.point_step = step;
  r.points = e.count;
  r.data.assign(r.points * r.point_step, 0);
  for (std::size_t i = 0; i < r.points; ++i) {
    c.start_instance();
    for (const auto& f : r.fields) c.next(f.datatype, r.data.data() + i * r.point_step + f.offset);
    c.end_instance();
  }
  return r;
}

}  // namespace

CloudRecords read_ply(const std::filesystem::path& file) {
  const auto bytes = read_file_bytes(file);
  return parse_ply(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file);
}

CloudRecords parse_ply(std::string_view text, const std::filesystem::path& file) {
  const Header h = parse_header(file, text);
  Cursor c{file, text.substr(h.body), h.format, 0, h.lines, {}, 0};
  std::optional<CloudRecords> vertices;
  std::map<std::string, double> camera;
  for (const auto& e : h.elements) {
    const std::uint64_t need = min_instance_bytes(e, h.format);
    // An ascii body's very last value needs no newline.
    const std::uint64_t left = c.body.size() - c.pos + (h.format == Format::kAscii ? 1 : 0);
    if (need > 0 && e.count > left / need) {
      fail(file, "element '" + printable(e.name) + "' claims " + std::to_string(e.count) +
                     " entries; the rest of the file holds at most " + std::to_string(left / need));
    }
    if (e.name == "vertex" && !vertices) {
      vertices = read_vertices(c, e);
    } else if (e.name == "camera" && e.count == 1) {
      c.start_instance();
      for (const auto& p : e.properties) {
        if (p.count_type != 0) fail(file, "camera property '" + p.name + "' is a list");
        camera[p.name] = c.next(p.type);
      }
      c.end_instance();
    } else if (!e.properties.empty()) {
      for (std::uint64_t k = 0; k < e.count; ++k) skip_instance(c, e);
    }
  }
  if (!vertices) fail(file, "has no vertex element");
  vertices->viewpoint = camera_pose(file, camera);
  return std::move(*vertices);
}

}  // namespace cleanmap
