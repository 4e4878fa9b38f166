// Scans with no valid point inside a log (issue 14, defects 7, 8 and 9): every input point
// still gets its score and label, each such scan is named once on stderr and in summary.json,
// and a log with no valid point at all is an error that says so.
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/label_file.hpp"
#include "io/score_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;

void write_nan_pcd(const fs::path& file, std::size_t n) {
  std::ofstream f(file);
  f << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << n << "\nHEIGHT 1\nPOINTS " << n
    << "\nDATA ascii\n";
  for (std::size_t i = 0; i < n; ++i) f << "nan nan nan\n";
}

fs::path small_log(const test::TempDir& dir) {
  std::string out;
  EXPECT_EQ(test::run_cleanmap("demo --generate-only --scans 5 --beams 16 --columns 256 --out " + (dir / "demo").string(), &out), 0)
      << out;
  return dir / "demo" / "sequence";
}

TEST(BadScans, AllNanAndEmptyScansKeepOneOutputPerInputPointAndAreNamed) {
  test::TempDir dir;
  const fs::path log = small_log(dir);
  const std::size_t n = read_labels(log / "labels" / "000001.label").size();
  write_nan_pcd(log / "scans" / "000001.pcd", n);  // its labels file still has n entries
  write_nan_pcd(log / "scans" / "000002.pcd", 0);
  std::ofstream(log / "labels" / "000002.label", std::ios::trunc).close();
  std::string out;
  ASSERT_EQ(test::run_cleanmap("run --input " + log.string() + " --out " + (dir / "out").string() +
                                   " --use-given-poses --voxel-size 0.3 --window-half 1", &out), 0) << out;
  const auto scores = read_scores(dir / "out" / "scores" / "000001.bin");
  const auto labels = read_labels(dir / "out" / "labels" / "000001.label");
  ASSERT_EQ(scores.size(), n);  // were 0-byte files
  ASSERT_EQ(labels.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_TRUE(std::isnan(scores[i]));
    EXPECT_EQ(labels[i], kLabelUnscored);
  }
  EXPECT_NE(out.find("warning: scan 000001: all " + std::to_string(n) + " points have NaN"), std::string::npos) << out;
  EXPECT_NE(out.find("warning: scan 000002: no points"), std::string::npos) << out;
  const auto s = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  ASSERT_EQ(s["empty_scans"].size(), 2u);
  EXPECT_EQ(s["empty_scans"][1]["scan"], "000002");
}

TEST(BadScans, AnEmptyScanStillHasItsLabelCountChecked) {
  test::TempDir dir;
  const fs::path log = small_log(dir);
  write_nan_pcd(log / "scans" / "000002.pcd", 0);  // its labels file keeps the old scan's labels
  std::string out;
  EXPECT_EQ(test::run_cleanmap("run --input " + log.string() + " --out " + (dir / "out").string() +
                                   " --use-given-poses --voxel-size 0.3 --window-half 1", &out), 1) << out;
  EXPECT_NE(out.find("000002.label: has "), std::string::npos) << out;
  EXPECT_NE(out.find("but its scan has 0 points"), std::string::npos) << out;
}

TEST(BadScans, ALogWithoutAnyValidPointIsAnErrorThatSaysSo) {
  test::TempDir dir;
  fs::create_directories(dir / "log");
  write_nan_pcd(dir / "log" / "000000.pcd", 10);
  write_nan_pcd(dir / "log" / "000001.pcd", 0);
  for (const char* cmd : {"run", "odometry"}) {
    std::string out;
    EXPECT_EQ(test::run_cleanmap(std::string(cmd) + " --input " + (dir / "log").string() + " --out " +
                                     (dir / cmd).string(), &out), 1) << out;
    EXPECT_NE(out.find("no valid point in any of its 2 scans"), std::string::npos) << out;
    EXPECT_EQ(out.find("write failed"), std::string::npos) << out;
    EXPECT_EQ(out.find("done."), std::string::npos) << out;
  }
}

TEST(BadScans, ANonFiniteViewpointInADynamicMapFolderIsNamed) {
  test::TempDir dir;
  fs::create_directories(dir / "dm" / "pcd");
  for (const char* vp : {"0 0 0 1 0 0 0", "nan 0 0 1 0 0 0"}) {
    static int k = 0;
    std::ofstream f(dir / "dm" / "pcd" / ("00000" + std::to_string(k++) + ".pcd"));
    f << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT " << vp
      << "\nPOINTS 1\nDATA ascii\n1 2 3\n";
  }
  std::string out;
  EXPECT_EQ(test::run_cleanmap("run --input " + (dir / "dm").string() + " --out " + (dir / "out").string(), &out), 1) << out;
  EXPECT_NE(out.find("000001.pcd: VIEWPOINT must be 7 finite numbers"), std::string::npos) << out;
}

}  // namespace
}  // namespace cleanmap
