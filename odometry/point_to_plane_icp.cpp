#include "odometry/point_to_plane_icp.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace cleanmap {
namespace {

constexpr double kPlaneReuse = 0.05;  // x map voxel size (5 cm at KISS-ICP's 1 m voxels)
constexpr int kMinMatches = 30;       // fewer plane matches: too little to register

struct PlaneMatch {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // source, sensor frame
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // map plane
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // map plane point
  double weight = 0.0;     // planarity; 0 = no match
};

struct PointToPlane {
  PointToPlane(const PlaneMatch& m) : p(m.point), n(m.normal), c(m.centre), w(m.weight) {}
  template <typename T>
  bool operator()(const T* q, const T* t, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rot(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> trans(t);
    const Eigen::Matrix<T, 3, 1> moved = rot * p.cast<T>() + trans;
    r[0] = T(w) * n.cast<T>().dot(moved - c.cast<T>());
    return true;
  }
  Eigen::Vector3d p, n, c;
  double w;
};

// Plane of the k map points nearest to T p: normal = least-variance direction; planarity =
// (l1 - l0) / l2 of the sorted eigenvalues, high for surfaces, low for edges and clutter.
// A point whose plane was fitted at `fitted_at[i]` keeps it while it stays within `reuse` of
// there: after the first ICP steps the points move by millimetres, and refitting the same
// neighbours was most of the odometry's time.
void match_planes(const std::vector<Eigen::Vector3d>& source, const VoxelHashMap& map,
                  const Eigen::Isometry3d& pose, double threshold, int k, double reuse,
                  std::vector<PlaneMatch>& matches, std::vector<Eigen::Vector3d>& fitted_at) {
  if (matches.size() != source.size()) {
    matches.assign(source.size(), PlaneMatch{});
    fitted_at.assign(source.size(), Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()));
  }
  const double reuse_sq = reuse * reuse;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, source.size(), 256), [&](const auto& r) {
    std::vector<Eigen::Vector3d> nn;
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d q = pose * source[i];
      if ((q - fitted_at[i]).squaredNorm() <= reuse_sq) continue;
      fitted_at[i] = q;
      matches[i].weight = 0.0;
      // Plane neighbours come from within a voxel, whatever the correspondence threshold: the
      // map keeps its points min_spacing() apart, so a tight threshold (a still sensor's is
      // centimetres) would otherwise find no plane at all. The threshold gates the nearest one.
      map.nearest(q, k, map.voxel_size, nn);
      if (static_cast<int>(nn.size()) < std::max(3, k / 2)) continue;
      double closest_sq = std::numeric_limits<double>::infinity();
      for (const auto& p : nn) closest_sq = std::min(closest_sq, (p - q).squaredNorm());
      if (closest_sq > threshold * threshold) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& p : nn) mean += p;
      mean /= static_cast<double>(nn.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const auto& p : nn) cov += (p - mean) * (p - mean).transpose();
      // Closed form for 3x3 (Eigen's computeDirect): the iterative solver was 4% of the time.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(cov);
      const auto& l = eig.eigenvalues();
      if (!(l[2] > 1e-12)) continue;
      const double planarity = (l[1] - l[0]) / l[2];
      if (planarity < 0.1) continue;
      matches[i] = {source[i], eig.eigenvectors().col(0), mean, planarity};
    }
  });
}

// Smallest / largest eigenvalue of the point-to-plane information matrix: near zero when some
// direction of motion is unconstrained (a corridor, a single plane).
double conditioning(const std::vector<PlaneMatch>& matches, const Eigen::Isometry3d& pose) {
  Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
  for (const auto& m : matches) {
    if (m.weight <= 0) continue;
    Eigen::Matrix<double, 6, 1> j;
    j.head<3>() = (pose.linear() * m.point).cross(m.normal);
    j.tail<3>() = m.normal;
    h += m.weight * m.weight * j * j.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(h);
  return eig.eigenvalues()[5] > 0 ? eig.eigenvalues()[0] / eig.eigenvalues()[5] : 0.0;
}

bool settled(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double eps) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() < eps && Eigen::AngleAxisd(d.rotation()).angle() < eps;
}

// One Ceres solve over the current matches, Cauchy loss of scale gate / 3 (KISS-ICP's kernel
// of the adaptive threshold). Returns the residuals used and their RMS after the solve.
std::pair<int, double> solve_matches(const std::vector<PlaneMatch>& matches, double gate,
                                     int iterations, Eigen::Quaterniond& q, Eigen::Vector3d& t) {
  // The loss lives here, not in the problem: a problem that got no residual block never took
  // ownership of it, and it leaked (found by the LeakSanitizer build).
  ceres::CauchyLoss cauchy(gate / 3.0);
  ceres::Problem::Options po;
  po.enable_fast_removal = false;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  problem.AddParameterBlock(q.coeffs().data(), 4, new ceres::EigenQuaternionManifold);
  problem.AddParameterBlock(t.data(), 3);
  ceres::LossFunction* loss = &cauchy;
  int used = 0;
  for (const auto& m : matches) {
    if (m.weight <= 0) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointToPlane, 1, 4, 3>(new PointToPlane(m)),
                             loss, q.coeffs().data(), t.data());
    ++used;
  }
  if (used < kMinMatches) return {used, 0.0};
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = iterations;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return {used, std::sqrt(2.0 * summary.final_cost / used)};
}

}  // namespace

RegistrationResult register_point_to_plane(const std::vector<Eigen::Vector3d>& source,
                                           const VoxelHashMap& map,
                                           const Eigen::Isometry3d& initial,
                                           const GateSchedule& gates,
                                           const OdometryConfig& config) {
  RegistrationResult result;
  Eigen::Quaterniond q(initial.rotation());
  Eigen::Vector3d t = initial.translation();
  std::vector<PlaneMatch> matches;
  std::vector<Eigen::Vector3d> fitted_at;
  const double reuse = kPlaneReuse * map.voxel_size;
  double gate = std::max(gates.start, gates.end);
  for (int it = 0; it < config.max_icp_iterations; ++it) {
    const Eigen::Isometry3d before = Eigen::Translation3d(t) * q;
    match_planes(source, map, before, gate, config.normal_neighbors, reuse, matches, fitted_at);
    const auto [used, rms] = solve_matches(matches, gate, config.solver_iterations, q, t);
    result.correspondences = used;
    result.iterations = it + 1;
    if (used < kMinMatches) {
      result.degenerate = true;
      break;
    }
    result.rms_residual = rms;
    q.normalize();
    if (!settled(before, Eigen::Translation3d(t) * q, config.convergence)) continue;
    if (gate <= gates.end) {
      result.converged = true;
      break;
    }
    // Settled with a wide gate: narrow it (halving) and match again, so the final pose is
    // weighed with the gate the motion model has earned.
    gate = std::max(gates.end, 0.5 * gate);
    matches.clear();
  }
  result.pose = Eigen::Translation3d(t) * q.normalized();
  result.inlier_share = source.empty() ? 0.0 : static_cast<double>(result.correspondences) / source.size();
  if (!result.degenerate && conditioning(matches, result.pose) < 1e-5) result.degenerate = true;
  return result;
}

RegistrationResult register_point_to_point(const std::vector<Eigen::Vector3d>& source,
                                           const VoxelHashMap& map,
                                           const Eigen::Isometry3d& initial, double threshold,
                                           const OdometryConfig& config) {
  RegistrationResult result;
  result.pose = initial;
  std::vector<Eigen::Vector3d> nn;
  for (int it = 0; it < config.max_icp_iterations; ++it) {
    Eigen::Matrix3Xd src(3, static_cast<Eigen::Index>(source.size()));
    Eigen::Matrix3Xd dst(3, static_cast<Eigen::Index>(source.size()));
    Eigen::Index n = 0;
    for (const auto& p : source) {
      const Eigen::Vector3d q = result.pose * p;
      map.nearest(q, 1, threshold, nn);
      if (nn.empty()) continue;
      src.col(n) = q;
      dst.col(n) = nn.front();
      ++n;
    }
    result.correspondences = static_cast<int>(n);
    result.iterations = it + 1;
    if (n < 30) {
      result.degenerate = true;
      break;
    }
    const Eigen::Matrix4d step = Eigen::umeyama(src.leftCols(n), dst.leftCols(n), false);
    const Eigen::Isometry3d before = result.pose;
    result.pose = Eigen::Isometry3d(step) * result.pose;
    result.rms_residual = std::sqrt((Eigen::Isometry3d(step) * src.leftCols(n) - dst.leftCols(n)).colwise().squaredNorm().mean());
    if (settled(before, result.pose, config.convergence)) {
      result.converged = true;
      break;
    }
  }
  result.inlier_share = source.empty() ? 0.0 : static_cast<double>(result.correspondences) / source.size();
  return result;
}

}  // namespace cleanmap
