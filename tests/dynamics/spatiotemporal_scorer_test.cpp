#include "dynamics/spatiotemporal_scorer.hpp"

#include <random>

#include <tbb/global_control.h>

#include <cmath>

#include "dynamics/spatiotemporal_normal.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// The analytic cases: no ground split, no clusters, fixed voxel size matching the sampling.
ScorerConfig analytic_config(const std::string& mode) {
  ScorerConfig c;
  c.mode = mode;
  c.voxel_size = 0.049;
  c.window_half = 3;
  c.radius = 0.3;
  c.ground_aware = false;
  c.object_completion = false;
  return c;
}

// A square patch of the plane through `origin` with normal `normal`, sampled on a 5 cm grid,
// moved by `velocity` * stamp. Every point is at the scan stamp.
Scan plane_scan(double stamp, const Eigen::Vector3d& normal, const Eigen::Vector3d& velocity,
                double half_size = 1.5, double step = 0.05) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  std::vector<Eigen::Vector3f> pts;
  for (double a = -half_size; a <= half_size + 1e-9; a += step) {
    for (double b = -half_size; b <= half_size + 1e-9; b += step) {
      pts.push_back((a * u + b * w + velocity * stamp).cast<float>());
    }
  }
  Scan s;
  s.points.resize(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) s.points.col(static_cast<Eigen::Index>(i)) = pts[i];
  s.stamp = stamp;
  s.pose = Eigen::Isometry3d::Identity();
  return s;
}

// Scores of the points of the middle scan within 0.5 m of the patch centre (no edge effects).
std::vector<float> central_scores(const ScorerConfig& cfg, const Eigen::Vector3d& normal,
                                  const Eigen::Vector3d& velocity) {
  SpatiotemporalScorer scorer(cfg);
  std::vector<ScoredScan> out;
  const int scans = 2 * cfg.window_half + 1;
  for (int k = 0; k < scans; ++k) {
    for (auto& s : scorer.push(plane_scan(0.1 * k, normal, velocity))) out.push_back(std::move(s));
  }
  for (auto& s : scorer.finish()) out.push_back(std::move(s));
  const ScoredScan& mid = out.at(static_cast<std::size_t>(cfg.window_half));
  EXPECT_EQ(mid.scans_before, cfg.window_half);
  EXPECT_EQ(mid.scans_after, cfg.window_half);
  const Eigen::Vector3d centre = velocity * 0.1 * cfg.window_half;
  std::vector<float> scores;
  for (std::size_t i = 0; i < mid.score.size(); ++i) {
    if ((mid.scan.points.col(static_cast<Eigen::Index>(i)).cast<double>() - centre).norm() < 0.5) {
      scores.push_back(mid.score[i]);
    }
  }
  EXPECT_GT(scores.size(), 100u);
  return scores;
}

class PlaneScores : public ::testing::TestWithParam<std::string> {};

TEST_P(PlaneScores, PlaneMovingAlongItsNormalScoresVOverSqrtOnePlusVSquared) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  for (double v : {0.1, 0.25, 0.5, 1.0, 2.0}) {
    const double expected = v / std::sqrt(1 + v * v);
    for (float s : central_scores(analytic_config(GetParam()), normal, v * normal)) {
      ASSERT_NEAR(s, expected, 2e-4) << "v = " << v;
    }
  }
}

TEST_P(PlaneScores, TimeScaleWeighsSecondsAgainstMetres) {
  ScorerConfig cfg = analytic_config(GetParam());
  cfg.time_scale = 2.0;  // t' = 2 t: the normal is (n, -v/2)
  const double v = 0.5;
  for (float s : central_scores(cfg, Eigen::Vector3d::UnitX(), v * Eigen::Vector3d::UnitX())) {
    ASSERT_NEAR(s, v / std::sqrt(4 + v * v), 2e-4);
  }
}

TEST_P(PlaneScores, StaticPlaneScoresZero) {
  for (float s : central_scores(analytic_config(GetParam()), Eigen::Vector3d::UnitZ(),
                                Eigen::Vector3d::Zero())) {
    ASSERT_NEAR(s, 0.0, 1e-4);
  }
}

TEST_P(PlaneScores, PlaneSlidingWithinItselfIsInvisible) {
  // The method's known blind spot: motion within the surface leaves the 4D normal spatial.
  for (float s : central_scores(analytic_config(GetParam()), Eigen::Vector3d::UnitZ(),
                                Eigen::Vector3d(1.5, 0.5, 0.0))) {
    ASSERT_NEAR(s, 0.0, 1e-4);
  }
}

INSTANTIATE_TEST_SUITE_P(BothModes, PlaneScores, ::testing::Values("exact", "fast"));

TEST(SpatiotemporalNormal, WallSeenAlongOneLine) {
  // One beam on a wall receding at v: samples (v t, 0, 0, t) lie on a line in 4D whose
  // normal in the x-t plane is (1, -v)/sqrt(1+v^2): its slope dx/dt is the velocity.
  for (double v : {0.2, 1.0, 3.0}) {
    Moments4 m;
    for (int k = 0; k < 40; ++k) {
      const double t = 0.01 * k;
      m.add(Eigen::Vector4d(2.0 + v * t, 0, 0, t));
    }
    EXPECT_NEAR(spatiotemporal_score(m, 10), v / std::sqrt(1 + v * v), 1e-6) << v;
  }
}

// The score from the characteristic polynomial equals the eigen solver's: on planes at any
// tilt, moving or not, with range noise, from one to eleven scans, on clutter scattered in 4D,
// and where the smallest eigenvalue is repeated (the solver's tie rule decides there).
TEST(SpatiotemporalNormal, PolynomialScoreEqualsTheEigenSolvers) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int fast = 0;
  for (int c = 0; c < 4000; ++c) {
    const Eigen::Vector3d n = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const double v = c % 3 == 0 ? 0.0 : 2.0 * u(rng), sigma = c % 5 == 0 ? 0.0 : 0.01 * (1 + u(rng));
    const int scans = 1 + c % 11;
    const bool clutter = c % 7 == 0;
    Moments4 m;
    for (int s = 0; s < scans; ++s) {
      const double t = 0.1 * (s - scans / 2);
      for (int k = 0; k < 12; ++k) {
        Eigen::Vector3d p = 0.3 * u(rng) * e1 + 0.3 * u(rng) * e2 + (v * t + sigma * noise(rng)) * n;
        if (clutter) p = 0.3 * Eigen::Vector3d(u(rng), u(rng), u(rng));
        m.add(Eigen::Vector4d(p.x(), p.y(), p.z(), t));
      }
    }
    for (double ratio : {0.0, 0.2}) {
      const float want = spatiotemporal_score_by_eigen_solver(m, 10, ratio);
      const float got = spatiotemporal_score(m, 10, ratio);
      if (std::isnan(want)) {
        EXPECT_TRUE(std::isnan(got)) << c;
      } else {
        ASSERT_NEAR(got, want, 2e-6) << "case " << c << " ratio " << ratio;
      }
    }
    fast += scans > 1 && sigma > 0;
  }
  EXPECT_GT(fast, 2000);
  // One scan alone (the time row is zero): the normal is repeated, and the tie rule gives 1.
  Moments4 one;
  for (int k = 0; k < 20; ++k) one.add(Eigen::Vector4d(0.01 * k, 0.02 * (k % 5), 0.0, 0.0));
  EXPECT_EQ(spatiotemporal_score(one, 10), spatiotemporal_score_by_eigen_solver(one, 10));
}

TEST(SpatiotemporalNormal, TooFewNeighboursIsNotScored) {
  Moments4 m;
  for (int k = 0; k < 9; ++k) m.add(Eigen::Vector4d(k, k * k, 1, 0));
  EXPECT_TRUE(std::isnan(spatiotemporal_score(m, 10)));
}

TEST(SpatiotemporalNormal, ShiftedMomentsEqualMomentsOfShiftedSamples) {
  Moments4 a, b;
  const Eigen::Vector4d d(1e4, -3e3, 20, 3600);
  for (int k = 0; k < 30; ++k) {
    const Eigen::Vector4d v = Eigen::Vector4d::Random();
    a.add(v + d);
    b.add(v);
  }
  const Moments4 s = a.shifted(d);
  EXPECT_NEAR((s.sum - b.sum).norm(), 0, 1e-6);
  EXPECT_NEAR((s.covariance() - b.covariance()).norm(), 0, 1e-6);
}

TEST(SpatiotemporalScorer, FastStatisticsMatchRecomputationAfterManyCycles) {
  ScorerConfig cfg = analytic_config("fast");
  cfg.window_half = 2;
  SpatiotemporalScorer scorer(cfg);
  // Far from the origin and hours into a log, so that naive sums would lose precision.
  const Eigen::Vector3d offset(3000, -2000, 50);
  for (int k = 0; k < 60; ++k) {
    Scan s = plane_scan(7200.0 + 0.1 * k, Eigen::Vector3d(1, 1, 0.2), Eigen::Vector3d(0.3, 0.1, 0), 1.0, 0.07);
    s.points.colwise() += offset.cast<float>();
    scorer.push(std::move(s));
    EXPECT_LE(scorer.window_size(), 5u);
  }
  EXPECT_LT(scorer.fast_statistics_drift(), 1e-8);
}

// Preparing every scan ahead of pushing it (a pipeline prepares scan i+1 while scan i is
// scored) gives the scores of push(Scan), bit for bit; a prepared scan pushed out of its order
// is refused.
TEST(SpatiotemporalScorer, ScansPreparedAheadScoreAsScansPushedWhole) {
  const auto cfg = analytic_config("fast");
  SpatiotemporalScorer whole(cfg), split(cfg);
  std::vector<PreparedScan> prepared;
  std::vector<ScoredScan> a, b;
  for (int k = 0; k < 9; ++k) {
    const Scan s = plane_scan(0.1 * k, Eigen::Vector3d(1, 0.2, 0), Eigen::Vector3d(0.5, 0, 0));
    for (auto& r : whole.push(s)) a.push_back(std::move(r));
    prepared.push_back(split.prepare(s));
  }
  for (auto& p : prepared) {
    for (auto& r : split.push(std::move(p))) b.push_back(std::move(r));
  }
  for (auto& r : whole.finish()) a.push_back(std::move(r));
  for (auto& r : split.finish()) b.push_back(std::move(r));
  ASSERT_EQ(a.size(), 9u);
  ASSERT_EQ(b.size(), 9u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].dynamic, b[k].dynamic);
    ASSERT_EQ(a[k].score.size(), b[k].score.size());
    for (std::size_t i = 0; i < a[k].score.size(); ++i) {
      EXPECT_TRUE(a[k].score[i] == b[k].score[i] ||
                  (std::isnan(a[k].score[i]) && std::isnan(b[k].score[i])));
    }
  }
  SpatiotemporalScorer order(cfg);
  auto first = order.prepare(plane_scan(0.0, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero()));
  auto second = order.prepare(plane_scan(0.1, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero()));
  EXPECT_THROW(order.push(std::move(second)), std::logic_error);
}

TEST(SpatiotemporalScorer, EveryScanIsScoredOnceWithTheWindowThatExists) {
  ScorerConfig cfg = analytic_config("fast");
  SpatiotemporalScorer scorer(cfg);
  std::vector<ScoredScan> out;
  for (int k = 0; k < 5; ++k) {  // fewer scans than one window (2N+1 = 7)
    auto r = scorer.push(plane_scan(0.1 * k, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero()));
    EXPECT_TRUE(r.empty());
  }
  for (auto& s : scorer.finish()) out.push_back(std::move(s));
  ASSERT_EQ(out.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {  // the whole log is every scan's window
    EXPECT_EQ(out[k].index, k);
    EXPECT_EQ(out[k].scans_before, static_cast<int>(k));
    EXPECT_EQ(out[k].scans_after, static_cast<int>(4 - k));
    EXPECT_EQ(out[k].score.size(), out[k].scan.size());
  }
}

TEST(SpatiotemporalScorer, LogEndsAreScoredWithAFullLengthOneSidedWindow) {
  ScorerConfig cfg = analytic_config("fast");  // N = 3
  SpatiotemporalScorer scorer(cfg);
  std::vector<ScoredScan> out;
  for (int k = 0; k < 10; ++k) {
    auto r = scorer.push(plane_scan(0.1 * k, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero()));
    // Scans 0..3 wait for scan 6, then one scan comes out per push, 3 scans late.
    EXPECT_EQ(r.size(), k < 6 ? 0u : k == 6 ? 4u : 1u) << k;
    for (auto& s : r) out.push_back(std::move(s));
  }
  for (auto& s : scorer.finish()) out.push_back(std::move(s));
  ASSERT_EQ(out.size(), 10u);
  for (std::size_t k = 0; k < 10; ++k) {
    const int i = static_cast<int>(k);
    EXPECT_EQ(out[k].index, k);
    EXPECT_EQ(out[k].scans_before + out[k].scans_after, 6) << k;  // always 2N+1 scans
    EXPECT_EQ(out[k].scans_before, i <= 3 ? i : i <= 6 ? 3 : i - 3) << k;
  }
}

TEST(SpatiotemporalScorer, ResultsDoNotDependOnThreadCount) {
  auto run = [](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    ScorerConfig cfg = analytic_config("fast");
    cfg.ground_aware = true;
    cfg.object_completion = true;
    SpatiotemporalScorer scorer(cfg);
    std::vector<float> all;
    for (int k = 0; k < 8; ++k) {
      for (auto& s : scorer.push(plane_scan(0.1 * k, Eigen::Vector3d(0.2, 0, 1), Eigen::Vector3d(0.4, 0, 0.4)))) {
        all.insert(all.end(), s.score.begin(), s.score.end());
      }
    }
    return all;
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_TRUE((std::isnan(one[i]) && std::isnan(two[i])) || one[i] == two[i]) << i;
  }
}

TEST(SpatiotemporalScorer, BadConfigNamesTheParameter) {
  ScorerConfig c;
  c.mode = "fastest";
  test::expect_error([&] { SpatiotemporalScorer s(c); }, {"mode", "fastest"});
  c = ScorerConfig{};
  c.radius = -1;
  test::expect_error([&] { SpatiotemporalScorer s(c); }, {"radius"});
}

}  // namespace
}  // namespace cleanmap
