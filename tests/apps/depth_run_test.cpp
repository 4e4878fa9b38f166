// Depth cameras end to end: the synthetic table scene (a camera on an arm, an object pushed by
// a hand) through `cleanmap run` with the arm preset as shipped, and `cleanmap demo --sensor depth`.
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/depth_image.hpp"
#include "io/label_file.hpp"
#include "simulation/synthetic_depth.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;

nlohmann::json summary_of(const fs::path& out) { return nlohmann::json::parse(std::ifstream(out / "summary.json")); }

// The bar is the issue's: moving-class IoU 0.8, with the arm's poses and with our odometry.
TEST(DepthRun, TheTableSceneIsCleanedWithGivenPosesAndWithOdometry) {
  test::TempDir dir;
  write_table_sequence(dir / "seq", make_table_scene(), 45, 30.0, 2);
  const std::string base = "run --input " + (dir / "seq").string() + " --config " +
                           (test::source_dir() / "config" / "rgbd-arm.yaml").string();
  for (const char* mode : {" --use-given-poses", ""}) {
    const fs::path out = dir / (std::string("out") + (*mode ? "-given" : "-odometry"));
    const auto r = test::cli(base + mode + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.output;
    const auto s = summary_of(out);
    EXPECT_EQ(s["layout"].get<std::string>(), "tum-rgbd");
    EXPECT_GE(s["moving"]["iou"].get<double>(), 0.8) << mode;
    EXPECT_GE(s["moving"]["precision"].get<double>(), 0.9) << mode;
    // Labels also as 16-bit masks, 255 where moving, pixel for pixel as the .label file.
    const std::string name = "100.500000";
    const auto labels = read_labels(out / "labels" / (name + ".label"), 320 * 240);
    const auto mask = read_png16(out / "labels" / (name + ".png"));
    ASSERT_EQ(mask.pixels.size(), labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) {
      ASSERT_EQ(mask.pixels[i], is_moving_label(labels[i]) ? 255 : 0) << i;
    }
  }
  // The odometry on depth clouds: within 1 cm of the arm's poses over the sweep.
  const auto r = test::cli("eval trajectory --est " + (dir / "out-odometry" / "poses_tum.txt").string() + " --ref " +
                           (dir / "seq" / "groundtruth.txt").string() + " --json " + (dir / "ape.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto ape = nlohmann::json::parse(std::ifstream(dir / "ape.json"));
  EXPECT_LT(ape["ape"]["translation"]["max"].get<double>(), 0.01) << ape.dump();
}

TEST(DepthRun, DemoWithTheDepthSensorRunsEndToEnd) {
  test::TempDir dir;
  const auto r = test::cli("demo --sensor depth --scans 40 --out " + dir.path.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("TUM RGB-D layout"), std::string::npos) << r.output;
  const auto s = summary_of(dir / "run");
  EXPECT_TRUE(s["complete"].get<bool>());
  EXPECT_GE(s["moving"]["iou"].get<double>(), 0.8);
  EXPECT_TRUE(fs::exists(dir / "run" / "map.bt"));
  EXPECT_TRUE(summary_of(dir.path)["complete"].get<bool>());
}

}  // namespace
}  // namespace cleanmap
