// How far DA can go at each SA on a DynamicMap ground truth, whatever the method: a dynamic
// point is removed only when no kept point lies within the distance (0.05 m), so freeing it
// costs every static point within that distance of it. Static points are given up
// cheapest-first (dynamic points with the fewest static neighbours freed first), and the SA
// left at each DA is printed. Greedy, so an estimate of the frontier, not a bound; its first
// row (no static point given up) is `eval map`'s DA ceiling.
//
//   dynamicmap_frontier --gt DIR/gt_cloud.pcd [--distance 0.05]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "apps/cli_fields.hpp"
#include "apps/map_truth.hpp"
#include "geometry/point_index.hpp"
#include "io/error.hpp"

using namespace cleanmap;

namespace {

void frontier(const std::filesystem::path& file, double distance) {
  const auto [gt, dynamic] = app::read_map_truth(file);
  std::vector<Eigen::Index> moving, standing;
  for (Eigen::Index i = 0; i < gt.points.cols(); ++i) (dynamic[static_cast<std::size_t>(i)] ? moving : standing).push_back(i);
  if (moving.empty() || standing.empty()) fail(file, "needs static and dynamic ground-truth points");
  const Eigen::Matrix3Xf stat = gt.points(Eigen::all, standing);
  const PointIndex index(stat);
  std::vector<std::vector<std::uint32_t>> shadow(moving.size());
  for (std::size_t k = 0; k < moving.size(); ++k) {
    index.for_each_within(gt.points.col(moving[k]), static_cast<float>(distance),
                          [&](std::uint32_t j, float) { shadow[k].push_back(j); });
  }
  std::vector<std::size_t> order(moving.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return shadow[a].size() < shadow[b].size(); });
  // Rows at these DAs (%), after the ceiling.
  const std::vector<double> rows{40, 50, 60, 70, 80, 85, 90, 95};
  std::vector<std::uint8_t> dropped(standing.size(), 0);
  std::size_t lost = 0, freed = 0, row = 0;
  const auto sa = [&] { return 100.0 * (1.0 - static_cast<double>(lost) / static_cast<double>(standing.size())); };
  const auto da = [&] { return 100.0 * static_cast<double>(freed) / static_cast<double>(moving.size()); };
  std::printf("%8s %10s\n", "DA", "SA at most");
  bool ceiling = false;
  for (const auto k : order) {
    if (!ceiling && !shadow[k].empty()) {
      std::printf("%8.2f %10.2f   (the ceiling: every static point kept)\n", da(), 100.0);
      ceiling = true;
      while (row < rows.size() && rows[row] <= da()) ++row;
    }
    for (const auto j : shadow[k]) {
      lost += !dropped[j];
      dropped[j] = 1;
    }
    ++freed;
    if (row < rows.size() && da() >= rows[row]) {
      std::printf("%8.2f %10.2f\n", da(), sa());
      ++row;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Greedy DA/SA frontier of a DynamicMap ground truth"};
  std::string file;
  double distance = 0.05;
  app.add_option("--gt", file, "gt_cloud.pcd (intensity 0 static, 1 dynamic)")->required();
  app.add_option("--distance", distance, "Kept when an output point is this close, m")
      ->check(app::number_in(pipeline::kPositive))->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    frontier(file, distance);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynamicmap_frontier: %s\n", e.what());  // names the file already
    return 1;
  }
  return 0;
}
