#include "mapping/point_cloud_map.hpp"

#include <cstring>

namespace cleanmap {

void PointCloudMap::add(const Scan& scan, const std::vector<std::uint8_t>& keep,
                        const std::vector<float>& score, std::size_t scan_index) {
  has_intensity_ = has_intensity_ && scan.has_intensity();
  const double inv = voxel_ > 0 ? 1.0 / voxel_ : 0.0;
  std::vector<std::int32_t> kept;
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    if (!keep[static_cast<std::size_t>(i)]) continue;
    if (voxel_ > 0 && !seen_.insert(voxel_of(scan.points.col(i), inv))) continue;
    kept.push_back(static_cast<std::int32_t>(i));
  }
  if (kept.empty()) return;
  std::vector<float> block(kRow * kept.size());
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const auto i = kept[j];
    float* row = block.data() + kRow * j;
    row[0] = scan.points(0, i);
    row[1] = scan.points(1, i);
    row[2] = scan.points(2, i);
    row[3] = scan.has_intensity() ? scan.intensity[i] : 0.0f;
    row[4] = score[static_cast<std::size_t>(i)];
    row[5] = static_cast<float>(scan_index);
  }
  blocks_.push_back(std::move(block));
  size_ += kept.size();
}

void PointCloudMap::write(const std::vector<std::filesystem::path>& files) const {
  PackedCloud cloud;
  cloud.fields = {"x", "y", "z"};
  if (has_intensity_) cloud.fields.emplace_back("intensity");
  cloud.fields.emplace_back("score");
  cloud.fields.emplace_back("scan");
  const std::size_t width = cloud.fields.size();
  cloud.data.resize(4 * width * size_);
  auto* out = reinterpret_cast<float*>(cloud.data.data());
  for (const auto& block : blocks_) {
    if (has_intensity_) {  // the rows as they are
      std::memcpy(out, block.data(), block.size() * sizeof(float));
      out += block.size();
      continue;
    }
    for (std::size_t r = 0; r < block.size(); r += kRow, out += width) {  // without intensity
      std::memcpy(out, block.data() + r, 3 * sizeof(float));
      std::memcpy(out + 3, block.data() + r + 4, 2 * sizeof(float));
    }
  }
  CloudWriteOptions options;
  options.viewpoint = Eigen::Isometry3d::Identity();
  for (const auto& file : files) write_packed_cloud(file, cloud, options);
}

Eigen::Matrix3Xf PointCloudMap::points() const {
  Eigen::Matrix3Xf p(3, static_cast<Eigen::Index>(size_));
  Eigen::Index c = 0;
  for (const auto& block : blocks_) {
    for (std::size_t r = 0; r < block.size(); r += kRow) p.col(c++) << block[r], block[r + 1], block[r + 2];
  }
  return p;
}

}  // namespace cleanmap
