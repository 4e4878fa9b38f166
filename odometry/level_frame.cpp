#include "odometry/level_frame.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

namespace cleanmap {

std::optional<Eigen::Matrix3d> level_rotation(const Eigen::Matrix3Xf& p, double inlier) {
  const Eigen::Index n = p.cols();
  if (n < 3) return std::nullopt;
  // At most 5000 points vote (every k-th), 300 tries with a fixed seed: a plane holding 40% of
  // them is drawn (three of its points) with probability 0.064 per try, missed by all 300 with
  // probability 2e-9; one holding the least accepted 20%, with 0.09.
  const Eigen::Index step = std::max<Eigen::Index>(1, n / 5000);
  std::vector<Eigen::Index> idx;
  for (Eigen::Index i = 0; i < n; i += step) idx.push_back(i);
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, idx.size() - 1);
  Eigen::Vector3d best_n = Eigen::Vector3d::Zero(), best_a = Eigen::Vector3d::Zero();
  std::size_t best = 0;
  for (int t = 0; t < 300; ++t) {
    const Eigen::Vector3d a = p.col(idx[pick(rng)]).cast<double>(), b = p.col(idx[pick(rng)]).cast<double>(),
                          c = p.col(idx[pick(rng)]).cast<double>();
    Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-9) continue;
    normal.normalize();
    // Up points from the plane towards the camera (the sensor origin looks at the support).
    if (normal.dot(-a) < 0) normal = -normal;
    if (-normal.y() < std::cos(60.0 * M_PI / 180.0)) continue;  // a wall or a ceiling
    std::size_t count = 0;
    for (const auto i : idx) count += std::abs(normal.dot(p.col(i).cast<double>() - a)) < inlier;
    if (count > best) {
      best = count;
      best_n = normal;
      best_a = a;
    }
  }
  if (best * 5 < idx.size()) return std::nullopt;
  // Three points fix the plane to their noise: refit it to all its inliers (least squares).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  std::size_t n_in = 0;
  for (const auto i : idx) {
    const Eigen::Vector3d q = p.col(i).cast<double>();
    if (std::abs(best_n.dot(q - best_a)) >= inlier) continue;
    mean += q;
    cov += q * q.transpose();
    ++n_in;
  }
  mean /= static_cast<double>(n_in);
  cov = cov / static_cast<double>(n_in) - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d refit = eig.eigenvectors().col(0);
  best_n = refit.dot(best_n) > 0 ? refit : -refit;
  return Eigen::Quaterniond::FromTwoVectors(best_n, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace cleanmap
