#include "mapping/point_cloud_map.hpp"

namespace cleanmap {

void PointCloudMap::add(const Scan& scan, const std::vector<std::uint8_t>& keep,
                        const std::vector<float>& score, std::size_t scan_index) {
  has_intensity_ = has_intensity_ && scan.has_intensity();
  const double inv = voxel_ > 0 ? 1.0 / voxel_ : 0.0;
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    if (!keep[static_cast<std::size_t>(i)]) continue;
    const auto p = scan.points.col(i);
    if (voxel_ > 0 && !seen_.insert(voxel_of(p, inv))) continue;
    x_.push_back(p.x());
    y_.push_back(p.y());
    z_.push_back(p.z());
    intensity_.push_back(scan.has_intensity() ? scan.intensity[i] : 0.0f);
    score_.push_back(score[static_cast<std::size_t>(i)]);
    scan_.push_back(static_cast<float>(scan_index));
  }
}

void PointCloudMap::write(const std::filesystem::path& file) const {
  Scan cloud;
  const auto n = static_cast<Eigen::Index>(x_.size());
  cloud.points.resize(3, n);
  cloud.points.row(0) = Eigen::Map<const Eigen::RowVectorXf>(x_.data(), n);
  cloud.points.row(1) = Eigen::Map<const Eigen::RowVectorXf>(y_.data(), n);
  cloud.points.row(2) = Eigen::Map<const Eigen::RowVectorXf>(z_.data(), n);
  if (has_intensity_) cloud.intensity = Eigen::Map<const Eigen::VectorXf>(intensity_.data(), n);
  CloudWriteOptions options;
  options.viewpoint = Eigen::Isometry3d::Identity();
  write_cloud(file, cloud, {{"score", score_}, {"scan", scan_}}, options);
}

Eigen::Matrix3Xf PointCloudMap::points() const {
  Eigen::Matrix3Xf p(3, static_cast<Eigen::Index>(x_.size()));
  for (std::size_t i = 0; i < x_.size(); ++i) p.col(static_cast<Eigen::Index>(i)) << x_[i], y_[i], z_[i];
  return p;
}

}  // namespace cleanmap
