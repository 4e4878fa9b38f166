#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap {

// A 16-bit single-channel image (depth in raw units, or a label mask), row-major.
struct Image16 {
  int width = 0, height = 0;
  std::vector<std::uint16_t> pixels;
};

// PNG through Debian's libpng. Reading accepts only 16-bit greyscale (what depth cameras and the
// TUM RGB-D layout write); anything else, a cut file, or more than kMaxImageSide pixels a side
// is an Error naming the file (a header's size is checked before its pixels are allocated).
inline constexpr int kMaxImageSide = 16384;
// A stated limit on a depth image's pixels, checked from its header before any is allocated:
// 8.4 Mpx (4096 x 2048; 17 MB of samples, 100 MB of points). The largest depth sensors give
// 2.7 Mpx (ZED 2i, 2208 x 1242); a 16384 x 16384 PNG of zeros is 0.5 MB on disk and asked for
// 0.5 GB of samples and 3.2 GB of points (issue 45).
inline constexpr std::uint64_t kMaxImagePixels = 4096ull * 2048ull;
Image16 read_png16(const std::filesystem::path& file);
void write_png16(const std::filesystem::path& file, const Image16& image);

// Per-pixel labels (one per pixel, row-major) as a 16-bit mask PNG: 255 moving, 0 otherwise.
void write_label_mask(const std::filesystem::path& file, const std::vector<std::uint32_t>& labels, int width,
                      int height);

// A pinhole depth camera: intrinsics in pixels, raw depth units per metre (TUM RGB-D and Bonn:
// 5000; RealSense: 1000), the farthest depth kept, and optional radial-tangential distortion
// (k1 k2 p1 p2 k3, OpenCV's order) of the pixel coordinates.
struct DepthIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double depth_scale = 5000.0;
  double max_depth = 4.0;  // m
  double min_depth = 0.1;  // m: closer is below what these sensors measure
  std::optional<std::array<double, 5>> distortion;
};

// Reads camera.yaml (keys fx fy cx cy depth_scale max_depth min_depth distortion); unknown or
// non-finite values are Errors naming the file and key.
DepthIntrinsics read_depth_intrinsics(const std::filesystem::path& file);
void write_depth_intrinsics(const std::filesystem::path& file, const DepthIntrinsics& k);

// One point per pixel in image order (row by row), in the camera's optical frame (x right, y
// down, z forward), so labels map back to pixels: pixels with no depth (0), nearer than
// min_depth or beyond max_depth are NaN points, which the sequence drops and outputs fill.
Scan depth_to_scan(const Image16& depth, const DepthIntrinsics& k);

// The undistorted normalised coordinates of a pixel (the inverse of the distortion model, by
// fixed-point iteration as OpenCV's undistortPoints does).
std::array<double, 2> undistort(const DepthIntrinsics& k, double u, double v);

}  // namespace cleanmap
