// The scorer on the foundation's simulated street (rolling-shutter lidar, ground-truth poses,
// per-point moving labels): agreement of the two modes, and detection quality.
#include <cmath>

#include "dynamics/spatiotemporal_scorer.hpp"
#include "evaluation/dynamic_metrics.hpp"
#include "io/label_file.hpp"
#include "simulation/synthetic_lidar.hpp"
#include "odometry/deskew.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

struct Scene {
  std::vector<Scan> world_scans;  // placed with each point's true pose
  std::vector<std::vector<std::uint32_t>> labels;
};

const Scene& street() {
  static const Scene scene = [] {
    Scene s;
    LidarModel lidar;
    lidar.columns = 1024;
    const auto world = make_street_world(1);
    auto sim = simulate_sequence(world, lidar, 21, 1);
    s.labels = std::move(sim.labels);
    s.world_scans = to_world(sim.scans);
    return s;
  }();
  return scene;
}

ScorerConfig street_config() {
  ScorerConfig c;
  c.voxel_size = 0.1;
  c.window_half = 5;
  return c;
}

std::vector<ScoredScan> score_all(const ScorerConfig& cfg) {
  SpatiotemporalScorer scorer(cfg);
  std::vector<ScoredScan> out;
  for (const auto& s : street().world_scans) {
    for (auto& r : scorer.push(s)) out.push_back(std::move(r));
  }
  for (auto& r : scorer.finish()) out.push_back(std::move(r));
  return out;
}

// Moving-class confusion within 20 m of the sensor (the paper's evaluation range).
MovingConfusion evaluate(const std::vector<ScoredScan>& scored) {
  MovingConfusion total;
  for (const auto& r : scored) {
    const auto& gt = street().labels[r.index];
    const Eigen::Vector3f origin = r.scan.pose->translation().cast<float>();
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
      if ((r.scan.points.col(static_cast<Eigen::Index>(i)) - origin).norm() > 20.0f) continue;
      count(total, r.dynamic[i], is_moving_label(gt[i]));
    }
  }
  return total;
}

TEST(SyntheticStreet, FastModeAgreesWithExactMode) {
  ScorerConfig cfg = street_config();
  cfg.object_completion = false;
  cfg.upsample = "nearest";
  cfg.mode = "exact";
  const auto exact = score_all(cfg);
  cfg.mode = "fast";
  const auto fast = score_all(cfg);
  double sum = 0.0;
  std::size_t both = 0, agree = 0, one_nan = 0;
  for (std::size_t k = 0; k < exact.size(); ++k) {
    for (std::size_t i = 0; i < exact[k].score.size(); ++i) {
      const float a = exact[k].score[i], b = fast[k].score[i];
      if (std::isnan(a) || std::isnan(b)) {
        one_nan += std::isnan(a) != std::isnan(b);
        continue;
      }
      ++both;
      sum += std::abs(a - b);
      agree += exact[k].dynamic[i] == fast[k].dynamic[i];
    }
  }
  // The stated tolerance: mean |score difference| below 0.01, decisions agree on 99% of points,
  // and under 2% of points are scored by one mode only (fast mode includes whole cells whose
  // mean is within the radius, which moves the min_neighbors boundary).
  EXPECT_LT(sum / static_cast<double>(both), 0.01);
  EXPECT_GT(static_cast<double>(agree) / static_cast<double>(both), 0.99);
  EXPECT_LT(static_cast<double>(one_nan) / static_cast<double>(both), 0.02);
}

TEST(SyntheticStreet, MovingObjectsAreFoundAboveTheBar) {
  const auto c = evaluate(score_all(street_config()));
  // Bar: cars driving past show mostly sides and roofs that move within their own planes,
  // which no normal can see (see method.md): a car alongside the sensor scores ~0 everywhere
  // and only free-space evidence can remove it. Measured here (N = 5): IoU 0.50, precision
  // 0.76, recall 0.60; N = 10 gives 0.54 / 0.84 / 0.60.
  EXPECT_GT(c.iou(), 0.45) << "precision " << c.precision() << " recall " << c.recall();
  EXPECT_GT(c.precision(), 0.7);
}

TEST(SyntheticStreet, ObjectCompletionAndGroundAwarenessBeatThePaperFaithfulOutput) {
  ScorerConfig paper = street_config();
  paper.object_completion = false;
  paper.ground_aware = false;
  const double faithful = evaluate(score_all(paper)).iou();
  const double improved = evaluate(score_all(street_config())).iou();
  EXPECT_GT(improved, faithful + 0.05) << "paper-faithful IoU " << faithful;
}

}  // namespace
}  // namespace cleanmap
