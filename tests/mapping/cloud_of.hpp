#pragma once

#include <Eigen/Core>
#include <vector>

namespace cleanmap::test {

// Points written out one by one, as a 3 x N cloud.
inline Eigen::Matrix3Xf cloud(const std::vector<Eigen::Vector3f>& p) {
  Eigen::Matrix3Xf m(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = p[i];
  return m;
}

}  // namespace cleanmap::test
