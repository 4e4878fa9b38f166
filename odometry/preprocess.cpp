#include "odometry/preprocess.hpp"

#include <cmath>

namespace cleanmap {

Eigen::VectorXf times_from_azimuth(const Eigen::Matrix3Xf& points, double sweep_seconds) {
  Eigen::VectorXf t(points.cols());
  double turned = 0.0;  // clockwise from the first point, rad, unwrapped along the storage order
  double last = points.cols() > 0 ? std::atan2(points(1, 0), points(0, 0)) : 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const double az = std::atan2(points(1, i), points(0, i));  // (-pi, pi], counter-clockwise
    turned += std::remainder(last - az, 2 * M_PI);  // the step from the point stored before
    last = az;
    // Lasers fire a few degrees apart: the first column's points ahead of the first one
    // fired with it.
    t[i] = static_cast<float>(std::max(0.0, turned / (2 * M_PI)) * sweep_seconds);
  }
  return t;
}

Scan preprocess(const Scan& scan, const OdometryConfig& c, double sweep_seconds) {
  std::vector<std::int32_t> keep;
  keep.reserve(scan.size());
  const float lo = static_cast<float>(c.min_range * c.min_range);
  const float hi = static_cast<float>(c.max_range * c.max_range);
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    const float r = scan.points.col(i).squaredNorm();
    if (r >= lo && r <= hi) keep.push_back(static_cast<std::int32_t>(i));
  }
  Scan out = select_points(scan, keep);
  if (c.vertical_correction_deg != 0.0) {
    // KITTI's HDL-64 scans are tilted down by ~0.205 deg (as CT-ICP and KISS-ICP correct).
    const double angle = c.vertical_correction_deg * M_PI / 180.0;
    for (Eigen::Index i = 0; i < out.points.cols(); ++i) {
      const Eigen::Vector3d p = out.points.col(i).cast<double>();
      const Eigen::Vector3d axis = p.cross(Eigen::Vector3d::UnitZ());
      if (axis.norm() < 1e-9) continue;
      out.points.col(i) = (Eigen::AngleAxisd(angle, axis.normalized()) * p).cast<float>();
    }
  }
  if (!out.has_time() && c.time_from_azimuth && !out.empty()) {
    out.time = times_from_azimuth(out.points, sweep_seconds);
  }
  return out;
}

}  // namespace cleanmap
