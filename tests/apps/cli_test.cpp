// The command line as a user meets it: exit codes, one-line errors, outputs.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/label_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// The command's exit code and output.
test::CliResult run(const std::string& args) { return test::cli(args); }

TEST(Cli, UnknownOptionFails) {
  const auto r = run("demo --no-such-option");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("--no-such-option"), std::string::npos) << r.output;
}

TEST(Cli, HelpOnEverySubcommand) {
  const auto r = run("demo --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("--out"), std::string::npos);
  EXPECT_NE(r.output.find("--beams"), std::string::npos);
}

TEST(Cli, DemoWritesASequenceAndACompleteSummary) {
  test::TempDir dir;
  const auto r = run("demo --out " + dir.path.string() + " --scans 3 --beams 16 --columns 256");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"sequence/scans/000002.pcd", "sequence/labels/000002.label",
                        "sequence/poses.txt", "sequence/times.txt", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  }
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_TRUE(summary["complete"].get<bool>());
  EXPECT_EQ(summary["synthetic"]["beams"].get<int>(), 16);
  // Nothing printed by the libraries (OctoMap's "Writing N nodes ... done." broke the progress
  // lines), and one rate: the run's own, on its last line.
  EXPECT_EQ(r.output.find("done."), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Writing"), std::string::npos) << r.output;
  std::size_t rates = 0;
  for (auto p = r.output.find("scans/s"); p != std::string::npos; p = r.output.find("scans/s", p + 1)) ++rates;
  EXPECT_EQ(rates, 1u) << r.output;
}

TEST(Cli, ConfigValuesApplyAndCommandLineOverrides) {
  test::TempDir dir;
  std::ofstream(dir / "c.yaml") << "synthetic:\n  scans: 2\n  beams: 8\n  columns: 128\n";
  const auto r = run("demo --out " + (dir / "o").string() + " --config " +
                     (dir / "c.yaml").string() + " --beams 4");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "o" / "summary.json"));
  EXPECT_EQ(summary["synthetic"]["scans"].get<int>(), 2);
  EXPECT_EQ(summary["synthetic"]["beams"].get<int>(), 4);
}

TEST(Cli, UnknownConfigKeyIsAnErrorNamingFileAndKey) {
  test::TempDir dir;
  std::ofstream(dir / "c.yaml") << "synthetic:\n  scanz: 2\n";
  const auto r = run("demo --out " + (dir / "o").string() + " --config " + (dir / "c.yaml").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("c.yaml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("synthetic.scanz"), std::string::npos) << r.output;
  // One line, and no summary claiming completeness.
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  if (std::filesystem::exists(dir / "o" / "summary.json")) {
    const auto s = nlohmann::json::parse(std::ifstream(dir / "o" / "summary.json"));
    EXPECT_FALSE(s["complete"].get<bool>());
  }
}

}  // namespace
}  // namespace cleanmap

namespace cleanmap {
namespace {

TEST(CliEval, TrajectoryOfAFileAgainstItselfIsZeroAndJsonIsWritten) {
  test::TempDir dir;
  std::ofstream poses(dir / "p.txt");
  for (int i = 0; i < 200; ++i) poses << "1 0 0 " << i << " 0 1 0 0 0 0 1 0\n";
  poses.close();
  const auto r = run("eval trajectory --est " + (dir / "p.txt").string() + " --ref " +
                     (dir / "p.txt").string() + " --json " + (dir / "t.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(std::ifstream(dir / "t.json"));
  EXPECT_EQ(j["paired"].get<int>(), 200);
  EXPECT_NEAR(j["kitti"]["t_err_percent"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(j["ape"]["translation"]["rmse"].get<double>(), 0.0, 1e-9);
}

TEST(CliEval, MismatchedTrajectoriesAreAClearError) {
  test::TempDir dir;
  std::ofstream(dir / "a.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n";
  std::ofstream(dir / "b.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const auto r = run("eval trajectory --est " + (dir / "b.txt").string() + " --ref " + (dir / "a.txt").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("b.txt"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cleanmap

namespace cleanmap {
namespace {

TEST(CliCompare, RunsOdometryWithAndWithoutRemovalAndReportsBoth) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 12 --beams 32 --columns 512 --out " + dir.path.string()).code, 0);
  const auto r = run("compare --input " + (dir / "sequence").string() + " --out " + (dir / "cmp").string() +
                     " --voxel-size 0.2 --window-half 3");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("removal on"), std::string::npos);
  const auto s = nlohmann::json::parse(std::ifstream(dir / "cmp" / "summary.json"));
  EXPECT_TRUE(s["complete"].get<bool>());
  EXPECT_LT(s["removal_off"]["ape_rmse_m"].get<double>(), 0.2);
  EXPECT_LT(s["removal_on"]["ape_rmse_m"].get<double>(), 0.2);
  EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / "with" / "poses_kitti.txt"));
}

}  // namespace
}  // namespace cleanmap

namespace cleanmap {
namespace {

TEST(CliEval, DemoTumPosesEvaluateAgainstTheirGroundTruthAndFramesAreStated) {
  // The run's TUM stamps are mid-sweep (0.05 s after the ground truth's): they failed to
  // associate before; the reference is now interpolated at them.
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 8 --beams 32 --columns 512 --out " + dir.path.string()).code, 0);
  const auto r = run("eval trajectory --est " + (dir / "run" / "poses_tum.txt").string() + " --ref " +
                     (dir / "sequence" / "poses_tum.txt").string() + " --json " + (dir / "t.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto t = nlohmann::json::parse(std::ifstream(dir / "t.json"));
  EXPECT_EQ(t["paired"].get<int>(), 7);  // the last lies 0.05 s beyond the ground truth's end
  EXPECT_LT(t["rpe"]["translation"]["rmse"].get<double>(), 0.05);
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(dir / "run" / "summary.json"));
  EXPECT_NE(s["pose_files"]["poses_tum.txt"].get<std::string>().find("lidar"), std::string::npos);
  EXPECT_NE(s["pose_files"]["poses.txt"].get<std::string>().find("lidar"), std::string::npos);
}

TEST(CliEval, AFrameMismatchIsWarnedAbout) {
  test::TempDir dir;
  std::ofstream cam(dir / "cam.txt"), lidar(dir / "lidar.txt");
  for (int k = 0; k < 10; ++k) {
    cam << "1 0 0 0 0 1 0 0 0 0 1 " << 0.7 * k << "\n";
    lidar << "1 0 0 " << 0.7 * k << " 0 1 0 0 0 0 1 0\n";
  }
  cam.close();
  lidar.close();
  const auto r = run("eval trajectory --est " + (dir / "lidar.txt").string() + " --ref " + (dir / "cam.txt").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the two trajectories head 90 deg apart"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cleanmap

namespace cleanmap {
namespace {

TEST(CliOdometry, WrittenScansFormASequenceThatScoreReads) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 8 --beams 32 --columns 512 --out " + dir.path.string()).code, 0);
  auto r = run("odometry --input " + (dir / "sequence").string() + " --out " + (dir / "odo").string() + " --write-scans");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"poses_kitti.txt", "poses_tum.txt", "poses.txt", "times.txt", "odometry_log.csv",
                        "scans/000007.pcd", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "odo" / f)) << f;
  }
  r = run("score --input " + (dir / "odo").string() + " --out " + (dir / "score").string() +
          " --voxel-size 0.2 --window-half 2");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(dir / "score" / "summary.json"));
  EXPECT_TRUE(s["complete"].get<bool>());
  EXPECT_EQ(s["scans"].get<int>(), 8);
}

}  // namespace
}  // namespace cleanmap

namespace cleanmap {
namespace {

// --mos-predictions: OUT/sequences/XX/predictions/NNNNNN.label as the SemanticKITTI MOS benchmark
// takes them: one label per velodyne point, 251 or 9 only, the moving ones those of labels/.
TEST(CliMosPredictions, ARealSequenceIsWrittenInTheBenchmarkLayout) {
  const auto seq = test::shared_data() / "semantickitti" / "07";
  if (!std::filesystem::exists(seq)) GTEST_SKIP() << seq << " missing";
  test::TempDir dir;
  const auto r = run("score --input " + seq.string() + " --out " + (dir / "s").string() + " --config " +
                     (test::source_dir() / "config" / "kitti-hdl64.yaml").string() + " --mos-predictions");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto pred = dir / "s" / "sequences" / "07" / "predictions";
  std::size_t files = 0, moving = 0, unscored = 0;
  for (const auto& e : std::filesystem::directory_iterator(seq / "velodyne")) {
    const std::string name = e.path().stem().string();
    const auto points = std::filesystem::file_size(e.path()) / 16;  // x y z intensity, float32
    const auto mos = read_labels(pred / (name + ".label"), points);
    const auto ours = read_labels(dir / "s" / "labels" / (name + ".label"), points);
    for (std::size_t i = 0; i < points; ++i) {
      ASSERT_TRUE(mos[i] == kLabelMoving || mos[i] == kLabelStatic) << name << " point " << i << ": " << mos[i];
      ASSERT_EQ(mos[i] == kLabelMoving, ours[i] == kLabelMoving) << name << " point " << i;
      moving += mos[i] == kLabelMoving;
      unscored += ours[i] == kLabelUnscored;
    }
    ++files;
  }
  EXPECT_EQ(files, 10u);
  EXPECT_GT(moving, 1000u);    // 07's walking people and cars
  EXPECT_GT(unscored, 1000u);  // static in the benchmark's file, 0 in labels/
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "s" / "summary.json"));
  EXPECT_EQ(summary["mos_predictions"].get<std::string>(), pred.string());
}

TEST(CliMosPredictions, TheSequenceNumberComesFromTheFolderOrTheOption) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 3 --beams 16 --columns 256 --out " + dir.path.string()).code, 0);
  const std::string input = " --input " + (dir / "sequence").string();
  auto r = run("run" + input + " --out " + (dir / "a").string() + " --use-given-poses --mos-predictions");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("is not a sequence number; give --mos-sequence XX"), std::string::npos) << r.output;
  r = run("run" + input + " --out " + (dir / "b").string() + " --use-given-poses --mos-predictions --mos-sequence 8");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "b" / "sequences" / "08" / "predictions" / "000002.label"));
  r = run("run" + input + " --out " + (dir / "c").string() + " --use-given-poses --mos-predictions --mos-sequence x1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("--mos-sequence 'x1': not a sequence number"), std::string::npos) << r.output;
}

// Issue 45 (Also): every numeric option's --help says the values it takes, from the table's
// range within what its type holds.
TEST(Cli, EveryNumericOptionShowsItsRangeInHelp) {
  const auto r = run("run --help");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto line_of = [&](const std::string& option) {
    const auto at = r.output.find("  " + option + " ");
    if (at == std::string::npos) return std::string();
    // An option's help may wrap onto the next line; the next option starts with "  --".
    const auto end = r.output.find("\n  --", at + 1);
    return r.output.substr(at, end == std::string::npos ? std::string::npos : end - at);
  };
  EXPECT_NE(line_of("--window-half").find("in [1, 1000]"), std::string::npos) << line_of("--window-half");
  EXPECT_NE(line_of("--radius").find("in [0.001, 100]"), std::string::npos) << line_of("--radius");
  EXPECT_NE(line_of("--self-mask-scans").find("in [1, 2147483647]"), std::string::npos) << line_of("--self-mask-scans");
  // Every INT or FLOAT option of the tables says it.
  std::size_t numeric = 0;
  for (std::size_t at = r.output.find("\n  --"); at != std::string::npos; at = r.output.find("\n  --", at + 1)) {
    const std::string option = r.output.substr(at + 3, r.output.find(' ', at + 3) - at - 3);
    const std::string line = line_of(option);
    if (line.find(" INT=") == std::string::npos && line.find(" FLOAT=") == std::string::npos) continue;
    if (line.find("FLOAT=[]") != std::string::npos) continue;  // a list (--crop-box): finite numbers
    ++numeric;
    const bool says = line.find("in [") != std::string::npos || line.find("in (") != std::string::npos ||
                      line.find("> ") != std::string::npos || line.find(">= ") != std::string::npos ||
                      line.find("finite") != std::string::npos;
    EXPECT_TRUE(says) << line;
  }
  EXPECT_GT(numeric, 50u);
}

// Issue 45 (8): an unreadable folder was "internal error: filesystem error", an unreadable
// preset "not valid YAML". Permissions do not bind root, so as root the command runs as
// nobody (setpriv); without either, there is nothing to test.
TEST(Cli, WhatCannotBeReadSaysPermissionDeniedAndNamesIt) {
  std::string prefix;
  if (::geteuid() == 0) {
    if (std::system("command -v setpriv > /dev/null 2>&1") != 0) GTEST_SKIP() << "root without setpriv";
    prefix = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  test::TempDir dir;
  namespace fs = std::filesystem;
  fs::permissions(dir.path, fs::perms::all);  // nobody writes the outputs here
  fs::create_directories(dir / "locked" / "velodyne");
  fs::permissions(dir / "locked", fs::perms::none);
  std::ofstream(dir / "secret.yaml") << "scorer_threshold: 0.3\n";
  fs::permissions(dir / "secret.yaml", fs::perms::none);
  const auto run_as = [&](const std::string& args) {
    test::CliResult r;
    const std::string cmd = prefix + CLEANMAP_BINARY + " " + args + " 2>&1";
    std::FILE* p = popen(cmd.c_str(), "r");
    char buf[4096];
    while (std::fgets(buf, sizeof buf, p)) r.output += buf;
    r.code = WEXITSTATUS(pclose(p));
    return r;
  };
  const auto folder = run_as("run --input " + (dir / "locked").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(folder.code, 1) << folder.output;
  EXPECT_NE(folder.output.find((dir / "locked").string() + ": permission denied"), std::string::npos) << folder.output;
  EXPECT_EQ(folder.output.find("internal error"), std::string::npos) << folder.output;
  const auto preset = run_as("config --config " + (dir / "secret.yaml").string());
  EXPECT_NE(preset.code, 0) << preset.output;
  EXPECT_NE(preset.output.find("secret.yaml: cannot be read (Permission denied)"), std::string::npos) << preset.output;
  EXPECT_EQ(preset.output.find("not valid YAML"), std::string::npos) << preset.output;
}


}  // namespace
}  // namespace cleanmap
