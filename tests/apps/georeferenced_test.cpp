// Georeferenced poses (issue 45): a log whose poses are at UTM-like coordinates is cleaned as
// the same log near the origin, in a local frame whose origin summary.json states.
#include <octomap/OcTree.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "io/pose_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The demo's log with its poses moved by `offset`, translations on a grid of 2^-8 m so that
// adding and removing the offset is exact in double (the runs can then agree to the bit).
void write_log(const std::filesystem::path& demo, const std::filesystem::path& log, const Eigen::Vector3d& offset) {
  std::filesystem::create_directories(log);
  std::filesystem::create_directory_symlink(demo / "scans", log / "scans");
  std::filesystem::copy_file(demo / "times.txt", log / "times.txt");
  std::filesystem::create_directory_symlink(demo / "labels", log / "labels");
  std::FILE* f = std::fopen((log / "poses.txt").c_str(), "w");
  for (const auto& p : read_poses(demo / "poses.txt")) {
    const Eigen::Matrix4d m = p.pose.matrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) std::fprintf(f, "%.17g ", m(r, c));
      const double t = std::round(m(r, 3) * 256.0) / 256.0 + offset[r];
      std::fprintf(f, r == 2 ? "%.10f\n" : "%.10f ", t);
    }
  }
  std::fclose(f);
}

nlohmann::json summary_of(const std::filesystem::path& run) {
  return nlohmann::json::parse(std::ifstream(run / "summary.json"));
}

TEST(Georeferenced, UtmPosesGiveTheSameCleanMapAsTheLogNearTheOrigin) {
  test::TempDir dir;
  ASSERT_EQ(test::run_cleanmap("demo --generate-only --scans 12 --out " + dir.path.string()), 0);
  const Eigen::Vector3d utm(500000.0, 5000000.0, 0.0);
  write_log(dir / "sequence", dir / "near", Eigen::Vector3d::Zero());
  write_log(dir / "sequence", dir / "utm", utm);
  const std::string opts = " --use-given-poses --voxel-size 0.1";
  for (const char* name : {"near", "utm"}) {
    std::string out;
    ASSERT_EQ(test::run_cleanmap("run --input " + (dir / name).string() + " --out " + (dir / (std::string(name) + "_run")).string() + opts, &out), 0) << out;
  }
  const auto near = summary_of(dir / "near_run"), far = summary_of(dir / "utm_run");
  EXPECT_EQ(near["map_origin"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(far["map_origin"], nlohmann::json({utm.x(), utm.y(), utm.z()}));
  EXPECT_EQ(far["octomap_points_beyond_reach"].get<int>(), 0);
  EXPECT_GT(far["dynamic_points"].get<int>(), 100);
  EXPECT_EQ(near["dynamic_points"], far["dynamic_points"]);
  EXPECT_EQ(near["octomap_leaves"], far["octomap_leaves"]);
  for (int i = 0; i < 12; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "labels/%06d.label", i);
    EXPECT_EQ(bytes_of(dir / "near_run" / name), bytes_of(dir / "utm_run" / name)) << name;
  }
  // The map files are in the local frame: world = map + map_origin, so the far run's files
  // equal the near run's, and their points differ from the poses' frame by the offset alone.
  for (const char* file : {"map_static.pcd", "map_static.ply", "map_dynamic.pcd", "map.bt"}) {
    EXPECT_EQ(bytes_of(dir / "near_run" / file), bytes_of(dir / "utm_run" / file)) << file;
  }
}

TEST(Georeferenced, AMapOriginFarFromTheLogIsAnErrorNotAnEmptyMap) {
  test::TempDir dir;
  ASSERT_EQ(test::run_cleanmap("demo --generate-only --scans 8 --out " + dir.path.string()), 0);
  write_log(dir / "sequence", dir / "utm", Eigen::Vector3d(500000.0, 5000000.0, 0.0));
  // The frame's own origin, 5,000 km away: what every run did before the local origin (its
  // 16-bit keys reach 9.8 km at 0.3 m, and the run exited 0 with an empty map).
  std::string out;
  EXPECT_EQ(test::run_cleanmap("run --online --input " + (dir / "utm").string() + " --out " + (dir / "run").string() +
                               " --use-given-poses --map-origin 0 0 0", &out), 1) << out;
  EXPECT_NE(out.find("every point lay beyond the OctoMap's reach"), std::string::npos) << out;
  EXPECT_FALSE(summary_of(dir / "run")["complete"].get<bool>());
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "map.bt"));
  // A malformed origin is refused by name before any work.
  const auto bad = test::cli("run --input " + (dir / "utm").string() + " --out " + (dir / "bad").string() +
                             " --use-given-poses --map-origin 1 2");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.output.find("--map-origin"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace cleanmap
