// What a clean OctoMap says about a DynamicMap ground truth: the share of its static points in
// occupied, free and unknown cells (a clean map keeps the world: occupied), and the same for
// its dynamic points (the trails a map should not keep: not occupied). The truth and the map
// must share a frame (a run on the same poses, as bench/quality.sh's are); points beyond the
// map's range limit from every pose stay unknown.
//
//   map_occupancy --map RUN/map.ot --gt DIR/gt_cloud.pcd [--json FILE]
#include <octomap/AbstractOcTree.h>
#include <octomap/OcTree.h>

#include <CLI/CLI.hpp>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/map_truth.hpp"
#include "io/error.hpp"
#include "mapping/cell_set.hpp"

using namespace cleanmap;

namespace {

std::unique_ptr<octomap::OcTree> read_tree(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) fail(file, "no such file");
  if (file.extension() == ".bt") {
    auto tree = std::make_unique<octomap::OcTree>(0.1);
    if (!tree->readBinary(file.string())) fail(file, "cannot read as a binary OctoMap (.bt)");
    return tree;
  }
  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(file.string()));
  if (!any) fail(file, "cannot read as an OctoMap (.ot)");
  if (!dynamic_cast<octomap::OcTree*>(any.get()))
    fail(file, "holds a " + any->getTreeType() + ", not an OcTree");
  return std::unique_ptr<octomap::OcTree>(static_cast<octomap::OcTree*>(any.release()));
}

// Per class (0 static, 1 dynamic, 2 dynamic in a cell without static truth): points in
// occupied, free, unknown cells.
using Tally = std::array<std::array<std::size_t, 3>, 3>;

Tally tally(const octomap::OcTree& tree, const app::MapTruth& truth) {
  const auto& p = truth.cloud.points;
  CellSet standing;
  octomap::OcTreeKey key;
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    if (!truth.dynamic[static_cast<std::size_t>(i)] &&
        tree.coordToKeyChecked(p(0, i), p(1, i), p(2, i), key)) {
      standing.insert({key[0], key[1], key[2]});
    }
  }
  Tally t{};
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const auto* node = tree.search(p(0, i), p(1, i), p(2, i));
    const auto state = static_cast<std::size_t>(!node ? 2 : tree.isNodeOccupied(node) ? 0 : 1);
    const bool dynamic = truth.dynamic[static_cast<std::size_t>(i)];
    ++t[dynamic][state];
    if (dynamic && !(tree.coordToKeyChecked(p(0, i), p(1, i), p(2, i), key) &&
                     standing.contains({key[0], key[1], key[2]}))) {
      ++t[2][state];
    }
  }
  return t;
}

double percent(std::size_t part, const std::array<std::size_t, 3>& all) {
  const std::size_t n = all[0] + all[1] + all[2];
  return n == 0 ? 0.0 : 100.0 * static_cast<double>(part) / static_cast<double>(n);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Shares of a DynamicMap ground truth's static and dynamic points in a map's occupied, free "
      "and unknown cells"};
  std::string map, gt, json;
  app.add_option("--map", map, "The clean map (.ot or .bt)")->required();
  app.add_option("--gt", gt, "gt_cloud.pcd (intensity 0 static, 1 dynamic), in the map's frame")
      ->required();
  app.add_option("--json", json, "Also write the shares (%) to this JSON file");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto truth = app::read_map_truth(gt);
    const auto tree = read_tree(map);
    const Tally t = tally(*tree, truth);
    nlohmann::json out;
    const char* names[] = {"static", "dynamic", "dynamic_alone"};
    const char* states[] = {"occupied", "free", "unknown"};
    std::printf("%-13s %10s %9s %9s %9s\n", "truth", "points", "occupied", "free", "unknown");
    for (int c = 0; c < 3; ++c) {
      const auto& row = t[static_cast<std::size_t>(c)];
      std::printf("%-13s %10zu %8.2f%% %8.2f%% %8.2f%%\n", names[c], row[0] + row[1] + row[2],
                  percent(row[0], row), percent(row[1], row), percent(row[2], row));
      for (int s = 0; s < 3; ++s) {
        out[std::string(names[c]) + "_" + states[s]] = percent(row[static_cast<std::size_t>(s)], row);
      }
    }
    if (!json.empty()) {
      std::ofstream f(json);
      f << out.dump(2) << "\n";
      if (!f) fail(json, "cannot write");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "map_occupancy: %s\n", e.what());  // names the file already
    return 1;
  }
  return 0;
}
