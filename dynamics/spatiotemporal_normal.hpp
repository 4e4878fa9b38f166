#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace cleanmap {

// Sufficient statistics of a set of 4-vectors v = (x, y, z, s*t): count, sum and sum of outer
// products, all relative to one local origin, so sums of far-away world coordinates or epoch
// times never cancel. Sums over disjoint sets add; removing a set subtracts.
struct Moments4 {
  double n = 0.0;
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  Eigen::Matrix4d sum_sq = Eigen::Matrix4d::Zero();

  void add(const Eigen::Vector4d& v) {
    n += 1.0;
    sum += v;
    sum_sq.noalias() += v * v.transpose();
  }
  Moments4& operator+=(const Moments4& o) {
    n += o.n;
    sum += o.sum;
    sum_sq += o.sum_sq;
    return *this;
  }
  Moments4& operator-=(const Moments4& o) {
    n -= o.n;
    sum -= o.sum;
    sum_sq -= o.sum_sq;
    return *this;
  }
  // The same statistics relative to origin + `shift`: sum(v - d) and sum((v - d)(v - d)^T).
  Moments4 shifted(const Eigen::Vector4d& d) const {
    Moments4 m;
    m.n = n;
    m.sum = sum - n * d;
    m.sum_sq = sum_sq - d * sum.transpose() - sum * d.transpose() + n * d * d.transpose();
    return m;
  }
  Eigen::Matrix4d covariance() const {
    const Eigen::Vector4d mean = sum / n;
    return sum_sq / n - mean * mean.transpose();
  }
};

// The paper's score: |time component| of the eigenvector of the smallest eigenvalue of the 4D
// covariance (Falque et al. 2023, Sec. III). NaN when fewer than `min_neighbors` points.
// Where the smallest eigenvalue is repeated (a line in 4D, e.g. a thin pole, or one beam on a
// wall) the normal is any unit vector of that eigenspace; the score is then the largest time
// component among them, |P e_t|, which equals |n_t| whenever the normal is unique.
// `max_eigen_ratio` (0 = off): a neighbourhood whose two smallest eigenvalues are within this
// ratio has no well-defined normal (vegetation, clutter scattered in 4D); it is not scored.
//
// Computed from the characteristic polynomial where the smallest eigenvalue is well apart
// from the next (spatiotemporal_normal.cpp), else by Eigen's solver (the reference, below).
float spatiotemporal_score(const Moments4& m, int min_neighbors, double max_eigen_ratio = 0.0);

// The same score by Eigen's SelfAdjointEigenSolver: tridiagonalisation and QR steps, about
// 0.7 us per neighbourhood, which was the scorer's largest cost (perf, online run on the
// Pandar64 street: 14 % of all samples).
float spatiotemporal_score_by_eigen_solver(const Moments4& m, int min_neighbors, double max_eigen_ratio = 0.0);

}  // namespace cleanmap
