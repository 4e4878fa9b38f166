#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace cleanmap {

// Sufficient statistics of a set of 4-vectors v = (x, y, z, s*t): count, sum and sum of outer
// products, all relative to one local origin, so sums of far-away world coordinates or epoch
// times never cancel. Sums over disjoint sets add; removing a set subtracts.
//
// The sum of outer products is symmetric: only its upper triangle is kept (10 of 16 entries),
// so moments are 120 bytes instead of 168. The scorer's window holds them per cell and each
// query adds up to 27 of them, after shifting each to its own origin: those sums and shifts
// were a sixth of an online run's time on the Pandar64 street.
struct Moments4 {
  // Entry k of `sq` is (kRow[k], kCol[k]) of the sum of outer products, row by row.
  static constexpr int kRow[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 3};
  static constexpr int kCol[10] = {0, 1, 2, 3, 1, 2, 3, 2, 3, 3};
  using Packed = Eigen::Matrix<double, 10, 1>;

  double n = 0.0;
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  Packed sq = Packed::Zero();

  void add(const Eigen::Vector4d& v) {
    n += 1.0;
    sum += v;
    for (int k = 0; k < 10; ++k) sq[k] += v[kRow[k]] * v[kCol[k]];
  }
  Moments4& operator+=(const Moments4& o) {
    n += o.n;
    sum += o.sum;
    sq += o.sq;
    return *this;
  }
  Moments4& operator-=(const Moments4& o) {
    n -= o.n;
    sum -= o.sum;
    sq -= o.sq;
    return *this;
  }
  // The same statistics relative to origin + `shift`: sum(v - d) and sum((v - d)(v - d)^T).
  Moments4 shifted(const Eigen::Vector4d& d) const {
    Moments4 m;
    m.n = n;
    m.sum = sum - n * d;
    const Eigen::Vector4d nd = n * d;
    for (int k = 0; k < 10; ++k) {
      const int i = kRow[k], j = kCol[k];
      m.sq[k] = sq[k] - d[i] * sum[j] - sum[i] * d[j] + nd[i] * d[j];
    }
    return m;
  }
  // The sum of outer products, both triangles.
  Eigen::Matrix4d sum_sq() const {
    Eigen::Matrix4d out;
    for (int k = 0; k < 10; ++k) out(kRow[k], kCol[k]) = out(kCol[k], kRow[k]) = sq[k];
    return out;
  }
  Eigen::Matrix4d covariance() const {
    const Eigen::Vector4d mean = sum / n;
    Eigen::Matrix4d out;
    for (int k = 0; k < 10; ++k) {
      const int i = kRow[k], j = kCol[k];
      out(i, j) = out(j, i) = sq[k] / n - mean[i] * mean[j];
    }
    return out;
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
