#include "io/depth_image.hpp"

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <string>

#include "io/close_checked.hpp"
#include "io/error.hpp"
#include "io/label_file.hpp"
#include "io/yaml_file.hpp"

namespace cleanmap {
namespace fs = std::filesystem;
namespace {

struct File {
  std::FILE* f;
  ~File() {
    if (f) std::fclose(f);
  }
};

// libpng reports through longjmp: its message is kept here and thrown once back in C++.
void on_png_error(png_structp png, png_const_charp message) {
  auto* why = static_cast<std::string*>(png_get_error_ptr(png));
  *why = message;
  png_longjmp(png, 1);
}
void on_png_warning(png_structp, png_const_charp) {}

// The calls libpng may leave by longjmp (an error jumps back to the setjmp of the function
// that called it): only plain data lives in these frames. A std::vector or std::string changed
// after setjmp has an indeterminate value after the jump (gcc -O1: -Wclobbered).
bool png_header(png_structp png, png_infop info, std::FILE* f) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_user_limits(png, kMaxImageSide, kMaxImageSide);
  png_init_io(png, f);
  png_read_info(png, info);
  return true;
}
bool png_pixels(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_swap(png);  // PNG stores 16-bit samples big-endian
  png_read_image(png, rows);
  return true;
}
bool png_write_all(png_structp png, png_infop info, std::FILE* f, png_uint_32 width, png_uint_32 height,
                   png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_IHDR(png, info, width, height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

bool read_rows(std::FILE* f, Image16& out, std::string& why) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &why, on_png_error, on_png_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  struct Destroy {
    png_structp* png;
    png_infop* info;
    ~Destroy() { png_destroy_read_struct(png, info, nullptr); }
  } destroy{&png, &info};
  if (!info || !png_header(png, info, f)) return false;
  if (png_get_bit_depth(png, info) != 16 || png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY) {
    why = "not a 16-bit greyscale image (bit depth " + std::to_string(png_get_bit_depth(png, info)) +
          ", colour type " + std::to_string(png_get_color_type(png, info)) + ")";
    return false;
  }
  out.width = static_cast<int>(png_get_image_width(png, info));
  out.height = static_cast<int>(png_get_image_height(png, info));
  if (static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height) > kMaxImagePixels) {
    why = std::to_string(out.width) + " x " + std::to_string(out.height) + " pixels: more than the " +
          std::to_string(kMaxImagePixels) + " (4096 x 2048) a depth image may have";
    return false;
  }
  out.pixels.resize(static_cast<std::size_t>(out.width) * out.height);
  std::vector<png_bytep> rows(static_cast<std::size_t>(out.height));
  for (int y = 0; y < out.height; ++y) rows[y] = reinterpret_cast<png_bytep>(out.pixels.data() + y * out.width);
  return png_pixels(png, rows.data());
}

double finite(const YAML::Node& n, const char* key, const fs::path& file) {
  double v = std::numeric_limits<double>::quiet_NaN();
  try {
    v = n[key].as<double>();
  } catch (const YAML::Exception&) {
    fail(file, std::string(key) + ": not a number");
  }
  if (!std::isfinite(v)) fail(file, std::string(key) + ": must be finite");
  return v;
}

}  // namespace

Image16 read_png16(const fs::path& file) {
  File f{std::fopen(file.c_str(), "rb")};
  if (!f.f) fail(file, "cannot open (no such file?)");
  Image16 out;
  std::string why = "out of memory";
  if (!read_rows(f.f, out, why)) fail(file, "unreadable PNG: " + why);
  return out;
}

void write_png16(const fs::path& file, const Image16& image) {
  File f{std::fopen(file.c_str(), "wb")};
  if (!f.f) fail(file, "cannot create file");
  std::string why = "out of memory";
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &why, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    rows[y] = reinterpret_cast<png_bytep>(const_cast<std::uint16_t*>(image.pixels.data() + y * image.width));
  }
  const bool ok = info && png_write_all(png, info, f.f, static_cast<png_uint_32>(image.width),
                                        static_cast<png_uint_32>(image.height), rows.data());
  png_destroy_write_struct(&png, &info);
  if (!ok) fail(file, "write failed: " + why);
}

void write_label_mask(const fs::path& file, const std::vector<std::uint32_t>& labels, int width, int height) {
  Image16 mask{width, height, std::vector<std::uint16_t>(labels.size())};
  if (labels.size() != static_cast<std::size_t>(width) * height) {
    fail(file, std::to_string(labels.size()) + " labels for a " + std::to_string(width) + "x" + std::to_string(height) + " image");
  }
  for (std::size_t i = 0; i < labels.size(); ++i) mask.pixels[i] = is_moving_label(labels[i]) ? 255 : 0;
  write_png16(file, mask);
}

DepthIntrinsics read_depth_intrinsics(const fs::path& file) {
  const YAML::Node root = load_yaml_file(file, "no such camera file (fx, fy, cx, cy, depth_scale in YAML)");
  if (!root.IsMap()) fail(file, "is not a map of camera settings");
  DepthIntrinsics k;
  for (const auto& kv : root) {
    // A key that is a list or a map (`[fx, fy]: 500`) has no name: yaml-cpp's conversion would
    // throw its own "bad conversion", naming nothing (issue 45).
    if (!kv.first.IsScalar()) fail(file, "a key that is a list or a map, not a setting's name (line " +
                                             std::to_string(kv.first.Mark().line + 1) + ")");
    const auto key = kv.first.Scalar();
    if (key == "fx") k.fx = finite(root, "fx", file);
    else if (key == "fy") k.fy = finite(root, "fy", file);
    else if (key == "cx") k.cx = finite(root, "cx", file);
    else if (key == "cy") k.cy = finite(root, "cy", file);
    else if (key == "depth_scale") k.depth_scale = finite(root, "depth_scale", file);
    else if (key == "max_depth") k.max_depth = finite(root, "max_depth", file);
    else if (key == "min_depth") k.min_depth = finite(root, "min_depth", file);
    else if (key == "distortion") {
      if (!kv.second.IsSequence() || kv.second.size() != 5) fail(file, "distortion: give five numbers, k1 k2 p1 p2 k3");
      std::array<double, 5> d{};
      for (int i = 0; i < 5; ++i) {
        d[i] = kv.second[i].as<double>(std::numeric_limits<double>::quiet_NaN());
        if (!std::isfinite(d[i])) fail(file, "distortion: value " + std::to_string(i + 1) + " is not a finite number");
      }
      k.distortion = d;
    } else {
      fail(file, "unknown key '" + key + "' (fx fy cx cy depth_scale max_depth min_depth distortion)");
    }
  }
  if (!(k.fx > 0) || !(k.fy > 0)) fail(file, "fx and fy must be given and positive (pixels)");
  if (!(k.depth_scale > 0)) fail(file, "depth_scale must be positive (raw units per metre)");
  if (!(k.max_depth > k.min_depth) || k.min_depth < 0) fail(file, "min_depth must be >= 0 and below max_depth");
  return k;
}

void write_depth_intrinsics(const fs::path& file, const DepthIntrinsics& k) {
  std::ofstream out(file);
  out.precision(10);
  out << "# Pinhole depth camera (pixels; depth_scale raw units per metre; depths in m)\n"
      << "fx: " << k.fx << "\nfy: " << k.fy << "\ncx: " << k.cx << "\ncy: " << k.cy << "\ndepth_scale: " << k.depth_scale
      << "\nmax_depth: " << k.max_depth << "\nmin_depth: " << k.min_depth << "\n";
  if (k.distortion) {
    const auto& d = *k.distortion;
    out << "distortion: [" << d[0] << ", " << d[1] << ", " << d[2] << ", " << d[3] << ", " << d[4] << "]\n";
  }
  close_checked(out, file);
}

std::array<double, 2> undistort(const DepthIntrinsics& k, double u, double v) {
  const double xd = (u - k.cx) / k.fx, yd = (v - k.cy) / k.fy;
  if (!k.distortion) return {xd, yd};
  const auto [k1, k2, p1, p2, k3] = *k.distortion;
  double x = xd, y = yd;
  for (int it = 0; it < 20; ++it) {  // converges in a few steps for lens-like coefficients
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dx = 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double dy = p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
  return {x, y};
}

Scan depth_to_scan(const Image16& depth, const DepthIntrinsics& k) {
  Scan s;
  const auto n = static_cast<Eigen::Index>(depth.pixels.size());
  s.points.resize(3, n);
  s.intensity = Eigen::VectorXf::Zero(n);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const Eigen::Index i = static_cast<Eigen::Index>(v) * depth.width + u;
      const double z = depth.pixels[static_cast<std::size_t>(i)] / k.depth_scale;
      if (!(z >= k.min_depth && z <= k.max_depth) || depth.pixels[static_cast<std::size_t>(i)] == 0) {
        s.points.col(i).setConstant(nan);
        continue;
      }
      const auto [x, y] = undistort(k, u, v);
      s.points.col(i) = Eigen::Vector3f(static_cast<float>(x * z), static_cast<float>(y * z), static_cast<float>(z));
    }
  }
  return s;
}

}  // namespace cleanmap
