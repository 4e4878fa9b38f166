#include "dynamics/spatiotemporal_normal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cleanmap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// det of the symmetric 3x3 block of `a` on rows/columns i, j, k, with `shift` off its diagonal.
double det3(const Eigen::Matrix4d& a, int i, int j, int k, double shift) {
  const double p = a(i, i) - shift, q = a(j, j) - shift, r = a(k, k) - shift;
  const double u = a(i, j), v = a(i, k), w = a(j, k);
  return p * (q * r - w * w) - u * (u * r - v * w) + v * (u * w - q * v);
}

double det4(const Eigen::Matrix4d& a) {
  const double s0 = a(0, 0) * a(1, 1) - a(1, 0) * a(0, 1), s1 = a(0, 0) * a(1, 2) - a(1, 0) * a(0, 2),
               s2 = a(0, 0) * a(1, 3) - a(1, 0) * a(0, 3), s3 = a(0, 1) * a(1, 2) - a(1, 1) * a(0, 2),
               s4 = a(0, 1) * a(1, 3) - a(1, 1) * a(0, 3), s5 = a(0, 2) * a(1, 3) - a(1, 2) * a(0, 3);
  const double c5 = a(2, 2) * a(3, 3) - a(3, 2) * a(2, 3), c4 = a(2, 1) * a(3, 3) - a(3, 1) * a(2, 3),
               c3 = a(2, 1) * a(3, 2) - a(3, 1) * a(2, 2), c2 = a(2, 0) * a(3, 3) - a(3, 0) * a(2, 3),
               c1 = a(2, 0) * a(3, 2) - a(3, 0) * a(2, 2), c0 = a(2, 0) * a(3, 1) - a(3, 0) * a(2, 1);
  return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
}

// The smallest root of a real-rooted monic polynomial (coefficients c[0] = 1, c[1], ... c[d],
// highest power first) by Newton's method from `from`, a point left of every root: from there
// the iterates rise monotonically to it (the polynomial keeps its sign and is convex or concave
// towards it). False when the iteration does not settle (a root nearly repeated converges only
// linearly: the caller falls back to the eigen solver).
template <int D>
bool smallest_root(const double (&c)[D + 1], double from, double scale, double& root) {
  double x = from;
  for (int it = 0; it < 80; ++it) {
    double p = c[0], dp = 0.0;
    for (int k = 1; k <= D; ++k) {
      dp = dp * x + p;
      p = p * x + c[k];
    }
    if (dp == 0.0) break;
    const double step = -p / dp;
    // Rounding ends the rise: a step back, or one below the precision of the scale.
    if (!(step > 1e-15 * scale)) {
      root = std::max(x, from);
      return true;
    }
    x += step;
  }
  root = x;
  return false;
}

}  // namespace

float spatiotemporal_score_by_eigen_solver(const Moments4& m, int min_neighbors, double max_eigen_ratio) {
  if (m.n < std::max(min_neighbors, 4)) return kNaN;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(m.covariance(), Eigen::ComputeEigenvectors);
  if (eig.info() != Eigen::Success) return kNaN;
  // Eigenvalues come sorted ascending: column 0 is the normal.
  const auto& lambda = eig.eigenvalues();
  if (max_eigen_ratio > 0 && lambda[0] > max_eigen_ratio * lambda[1]) return kNaN;
  const double tie = 1e-9 * std::max(lambda[3], 1e-30);
  double t_sq = 0.0;
  for (int k = 0; k < 4 && lambda[k] - lambda[0] <= tie; ++k) {
    t_sq += eig.eigenvectors()(3, k) * eig.eigenvectors()(3, k);
  }
  return static_cast<float>(std::min(1.0, std::sqrt(t_sq)));
}

// For C = [S c; c^T v] with a simple smallest eigenvalue l0 and unit eigenvector n,
// adj(C - l0 I) = prod_{k>0} (l_k - l0) n n^T. Its last diagonal entry is the cofactor
// det(S - l0 I), and prod_{k>0} (l_k - l0) = -p'(l0) for p(l) = det(C - l I). So
//   n_t^2 = det(S - l0 I) / -p'(l0),
// with l0 the smallest root of p: Newton from 0 (C is a covariance, every root >= 0), then the
// next root l1 from l0 on p / (l - l0). About 150 flops against the solver's tridiagonalisation
// and QR steps. Where l1 - l0 is within 1e-6 of the trace (a nearly repeated normal, and every
// neighbourhood from one scan alone, whose time row is zero) the solver decides, with its tie
// rule; so does a determinant that rounding left below zero.
float spatiotemporal_score(const Moments4& m, int min_neighbors, double max_eigen_ratio) {
  if (m.n < std::max(min_neighbors, 4)) return kNaN;
  const Eigen::Matrix4d a = m.covariance();
  // p(l) = l^4 - e1 l^3 + e2 l^2 - e3 l + e4, e_k the sums of the k x k principal minors.
  const double e1 = a.trace();
  double e2 = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) e2 += a(i, i) * a(j, j) - a(i, j) * a(i, j);
  }
  const double e3 = det3(a, 0, 1, 2, 0.0) + det3(a, 0, 1, 3, 0.0) + det3(a, 0, 2, 3, 0.0) + det3(a, 1, 2, 3, 0.0);
  const double e4 = det4(a);
  if (!(e1 > 0) || !(e4 > 0) || !std::isfinite(e2 + e3 + e4)) {
    return spatiotemporal_score_by_eigen_solver(m, min_neighbors, max_eigen_ratio);
  }
  double l0 = 0.0, l1 = 0.0;
  const double quartic[5] = {1.0, -e1, e2, -e3, e4};
  if (!smallest_root<4>(quartic, 0.0, e1, l0)) return spatiotemporal_score_by_eigen_solver(m, min_neighbors, max_eigen_ratio);
  // p / (l - l0), by synthetic division; its value at l0 is p'(l0).
  const double b2 = -e1 + l0, b1 = e2 + l0 * b2, b0 = -e3 + l0 * b1;
  const double cubic[4] = {1.0, b2, b1, b0};
  if (!smallest_root<3>(cubic, l0, e1, l1) || !(l1 - l0 > 1e-6 * e1)) {
    return spatiotemporal_score_by_eigen_solver(m, min_neighbors, max_eigen_ratio);
  }
  if (max_eigen_ratio > 0 && l0 > max_eigen_ratio * l1) return kNaN;
  const double dp = ((l0 + b2) * l0 + b1) * l0 + b0;  // p'(l0) < 0
  const double t_sq = det3(a, 0, 1, 2, l0) / -dp;
  return static_cast<float>(std::min(1.0, std::sqrt(std::max(0.0, t_sq))));
}

}  // namespace cleanmap
