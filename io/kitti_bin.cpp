#include "io/kitti_bin.hpp"

#include <fstream>
#include <vector>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap {

Scan read_kitti_bin(const std::filesystem::path& file) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read file (" + ec.message() + ")");
  if (bytes % 16 != 0) {
    fail(file, "size " + std::to_string(bytes) +
                   " bytes is not a multiple of 16 (x, y, z, remission float32); truncated?");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open file");
  const auto n = static_cast<Eigen::Index>(bytes / 16);
  Scan scan;
  scan.name = file.stem().string();
  if (n == 0) {
    // An empty scan; Eigen's row views of a 4x0 matrix offset a null pointer (UBSan, fuzz_kitti_bin).
    scan.points.resize(3, 0);
    return scan;
  }
  Eigen::Matrix4Xf raw(4, n);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes)) fail(file, "short read");
  scan.points = raw.topRows<3>();
  scan.intensity = raw.row(3).transpose();
  scan.input_size = static_cast<std::size_t>(n);
  return scan;
}

void write_kitti_bin(const std::filesystem::path& file, const Scan& scan) {
  if (scan.size() == 0) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);  // no row views of an empty matrix
    if (!out) fail(file, "cannot create file");
    return;
  }
  Eigen::Matrix4Xf raw(4, scan.points.cols());
  raw.topRows<3>() = scan.points;
  if (scan.has_intensity()) {
    raw.row(3) = scan.intensity.transpose();
  } else {
    raw.row(3).setZero();
  }
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file, "cannot create file");
  out.write(reinterpret_cast<const char*>(raw.data()),
            static_cast<std::streamsize>(raw.size() * sizeof(float)));
  close_checked(out, file);
}

}  // namespace cleanmap
