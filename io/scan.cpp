#include "io/scan.hpp"

#include <cmath>

namespace cleanmap {

std::string scan_name(std::size_t index) {
  std::string digits = std::to_string(index);
  return digits.size() >= 6 ? digits : std::string(6 - digits.size(), '0') + digits;
}

Scan select_points(const Scan& scan, const std::vector<std::int32_t>& indices) {
  Scan out;
  out.stamp = scan.stamp;
  out.pose = scan.pose;
  out.name = scan.name;
  out.input_size = scan.input_size ? scan.input_size : scan.size();
  const auto n = static_cast<Eigen::Index>(indices.size());
  out.points.resize(3, n);
  if (scan.has_time()) out.time.resize(n);
  if (scan.has_intensity()) out.intensity.resize(n);
  out.input_index.resize(indices.size());
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto i = indices[k];
    out.points.col(k) = scan.points.col(i);
    if (scan.has_time()) out.time[k] = scan.time[i];
    if (scan.has_intensity()) out.intensity[k] = scan.intensity[i];
    out.input_index[k] = scan.input_index.empty() ? i : scan.input_index[i];
  }
  return out;
}

DroppedPoints drop_invalid(Scan& scan) {
  std::vector<std::int32_t> keep;
  keep.reserve(scan.size());
  const bool timed = scan.has_time();
  DroppedPoints d;
  for (Eigen::Index i = 0; i < scan.points.cols(); ++i) {
    if (!scan.points.col(i).allFinite() || (timed && !std::isfinite(scan.time[i]))) {
      ++d.non_finite;
    } else if (!(scan.points.col(i).cwiseAbs().maxCoeff() <= kMaxCoordinate) ||
               (timed && !(std::abs(scan.time[i]) <= kMaxPointTime))) {
      ++d.out_of_range;
    } else {
      keep.push_back(static_cast<std::int32_t>(i));
    }
  }
  if (keep.size() < scan.size()) scan = select_points(scan, keep);
  return d;
}

}  // namespace cleanmap
