// Where outputs go (issue 14, defects 4, 5, 6, 13 and 14): a command never writes into its
// input, never mixes an earlier run's files with a new summary, and whatever stops it leaves
// summary.json with "complete": false and the reason.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "pipeline/output_dir.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;

// The command's exit code and output.
test::CliResult run(const std::string& args) { return test::cli(args); }

nlohmann::json summary(const fs::path& out) { return nlohmann::json::parse(std::ifstream(out / "summary.json")); }

// A 4-scan synthetic log with poses and labels, written once per test.
fs::path small_log(const test::TempDir& dir) {
  const auto r = run("demo --generate-only --scans 4 --beams 16 --columns 256 --out " + (dir / "demo").string());
  EXPECT_EQ(r.code, 0) << r.output;
  return dir / "demo" / "sequence";
}

const std::string kQuick = " --use-given-poses --voxel-size 0.3 --window-half 1";

std::string read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

TEST(OutputPolicy, OutEqualToOrInsideTheInputIsRefusedAndTheInputUntouched) {
  test::TempDir dir;
  const fs::path log = small_log(dir);
  const std::string poses = read(log / "poses.txt"), label = read(log / "labels" / "000001.label");
  for (const fs::path& out : {log, log / "out", log / ".." / "sequence"}) {
    const auto r = run("run --input " + log.string() + " --out " + out.string() + kQuick);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("the input"), std::string::npos) << r.output;
  }
  // The log inside OUT: --overwrite would remove it.
  const auto r = run("run --input " + log.string() + " --out " + (dir / "demo").string() + " --overwrite" + kQuick);
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("contains the input"), std::string::npos) << r.output;
  EXPECT_EQ(read(log / "poses.txt"), poses);
  EXPECT_EQ(read(log / "labels" / "000001.label"), label);
  EXPECT_FALSE(fs::exists(log / "summary.json"));
  EXPECT_FALSE(fs::exists(log / "out"));
}

TEST(OutputPolicy, AUsedFolderNeedsOverwriteWhichRemovesTheEarlierRun) {
  test::TempDir dir;
  const fs::path log = small_log(dir), out = dir / "out";
  ASSERT_EQ(run("run --input " + log.string() + " --out " + out.string() + kQuick).code, 0);
  std::ofstream(out / "labels" / "000099.label") << "stale";  // as an earlier, longer run left it
  const std::string before = read(out / "summary.json");
  auto r = run("run --input " + log.string() + " --out " + out.string() + kQuick);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("is not empty"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--overwrite"), std::string::npos) << r.output;
  EXPECT_EQ(read(out / "summary.json"), before);  // the refusal touched nothing
  r = run("run --input " + log.string() + " --out " + out.string() + " --overwrite" + kQuick);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "labels" / "000099.label"));
  EXPECT_TRUE(summary(out)["complete"].get<bool>());
  // A folder cleanmap did not write is never emptied.
  fs::create_directories(dir / "mine");
  std::ofstream(dir / "mine" / "notes.txt") << "keep";
  r = run("odometry --input " + log.string() + " --out " + (dir / "mine").string() + " --overwrite");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("no cleanmap summary.json"), std::string::npos) << r.output;
  EXPECT_EQ(read(dir / "mine" / "notes.txt"), "keep");
}

// Issue 45: --overwrite emptied any folder whose summary.json had a "command" key, and another
// tool's summary cost a user's thesis.tex. Only a summary with cleanmap's marker makes a folder
// cleanmap's, and even then a file cleanmap does not write stops the overwrite, untouched.
TEST(OutputPolicy, OverwriteRemovesOnlyWhatCleanmapWrites) {
  test::TempDir dir;
  const fs::path log = small_log(dir), other = dir / "other", out = dir / "out";
  fs::create_directories(other);
  std::ofstream(other / "summary.json") << R"({"command": "train", "complete": true})";
  std::ofstream(other / "thesis.tex") << "keep";
  auto r = run("run --input " + log.string() + " --out " + other.string() + " --overwrite" + kQuick);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("holds no cleanmap summary.json"), std::string::npos) << r.output;
  EXPECT_EQ(read(other / "thesis.tex"), "keep");
  EXPECT_FALSE(fs::exists(other / ".lock"));  // the refused folder is left as it was
  ASSERT_EQ(run("run --input " + log.string() + " --out " + out.string() + kQuick).code, 0);
  EXPECT_EQ(summary(out)["cleanmap_output"].get<int>(), 1);
  std::ofstream(out / "thesis.tex") << "keep";
  r = run("run --input " + log.string() + " --out " + out.string() + " --overwrite" + kQuick);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("holds 'thesis.tex', which cleanmap does not write"), std::string::npos) << r.output;
  EXPECT_EQ(read(out / "thesis.tex"), "keep");
  EXPECT_TRUE(fs::exists(out / "map.ot"));  // nothing was removed
}

TEST(OutputPolicy, EveryFailureLeavesAnIncompleteSummaryWithTheReason) {
  test::TempDir dir;
  const fs::path log = small_log(dir), out = dir / "out";
  ASSERT_EQ(run("run --input " + log.string() + " --out " + out.string() + kQuick).code, 0);
  ASSERT_TRUE(summary(out)["complete"].get<bool>());
  // Errors found before any output: a bad pose file, a bad preset, a missing input.
  std::ofstream(dir / "bad_poses.txt") << "1 0 0\n";
  std::ofstream(dir / "bad.yaml") << "scorer:\n  no_such_key: 1\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"run --input " + log.string() + " --poses " + (dir / "bad_poses.txt").string(), "bad_poses.txt"},
      {"run --input " + log.string() + " --config " + (dir / "bad.yaml").string(), "no_such_key"},
      {"odometry --input " + (dir / "missing").string(), "missing"},
      {"score --input " + log.string() + " --config " + (dir / "bad.yaml").string(), "bad.yaml"}};
  for (const auto& [args, fragment] : cases) {
    const auto r = run(args + " --out " + out.string() + " --overwrite");
    EXPECT_EQ(r.code, 1) << args << "\n" << r.output;
    const auto s = summary(out);
    EXPECT_FALSE(s["complete"].get<bool>()) << args;
    EXPECT_NE(s.value("error", "").find(fragment), std::string::npos) << args << ": " << s.dump();
  }
}

TEST(OutputPolicy, EmptyAndOverlongOutPathsAreOneLineErrors) {
  test::TempDir dir;
  const fs::path log = small_log(dir);
  auto r = run("odometry --input " + log.string() + " --out ''");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("--out: empty path"), std::string::npos) << r.output;
  r = run("odometry --input " + log.string() + " --out " + (dir / std::string(5000, 'a')).string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("too long"), std::string::npos) << r.output;
  EXPECT_LT(r.output.size(), 400u) << r.output;
}

TEST(OutputPolicy, CompareChecksItsReferenceBeforeAnyOdometry) {
  test::TempDir dir;
  const fs::path log = small_log(dir), out = dir / "out";
  const auto r = run("compare --input " + log.string() + " --ref " + (dir / "nope.txt").string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("nope.txt"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "without"));  // failed before the first pass
  EXPECT_FALSE(summary(out)["complete"].get<bool>());
}

// A demo run under way (400 scans: tens of seconds), its process.
pid_t start_demo(const fs::path& out) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execl(CLEANMAP_BINARY, CLEANMAP_BINARY, "demo", "--scans", "400", "--beams", "16", "--columns", "256", "--out",
          out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
}

// Waits until the demo's run is under way (its sixth scan is written).
void wait_under_way(const fs::path& out) {
  for (int k = 0; k < 600 && !fs::exists(out / "sequence" / "scans" / "000005.pcd"); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

// A demo run under way, then `sig`: its exit status.
int exit_after_signal(const fs::path& out, int sig) {
  const pid_t pid = start_demo(out);
  if (pid < 0) return -1;
  wait_under_way(out);
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

TEST(OutputPolicy, CtrlCStopsAtTheNextScanAndSaysSoInTheSummary) {
  test::TempDir dir;
  const fs::path out = dir / "out";
  EXPECT_EQ(exit_after_signal(out, SIGINT), 130);
  const auto s = summary(out);
  EXPECT_FALSE(s["complete"].get<bool>());
  EXPECT_NE(s.value("error", "").find("interrupted by SIGINT"), std::string::npos) << s.dump();
}

TEST(OutputPolicy, SigtermStopsAtTheNextScanAndExits143) {
  test::TempDir dir;
  const fs::path out = dir / "out";
  EXPECT_EQ(exit_after_signal(out, SIGTERM), 143);  // 128 + SIGTERM, as a shell reports it (issue 45: it was 130)
  const auto s = summary(out);
  EXPECT_FALSE(s["complete"].get<bool>());
  EXPECT_NE(s.value("error", "").find("interrupted by SIGTERM"), std::string::npos) << s.dump();
}

// Two commands on one OUT (issue 45: B's --overwrite emptied OUT while A wrote there, and A
// reported 100 scans complete beside 85 label files): B is refused, naming A, and touches nothing.
TEST(OutputPolicy, ASecondCommandOnAHeldOutIsRefusedNamingTheHolder) {
  test::TempDir dir;
  const fs::path out = dir / "out";
  const pid_t a = start_demo(out);
  ASSERT_GT(a, 0);
  wait_under_way(out);
  std::size_t before = 0;
  for ([[maybe_unused]] const auto& e : fs::recursive_directory_iterator(out)) ++before;
  const auto b = test::cli("demo --scans 5 --overwrite --out " + out.string());
  EXPECT_EQ(b.code, 1) << b.output;
  EXPECT_NE(b.output.find("in use by another cleanmap command (pid " + std::to_string(a)), std::string::npos) << b.output;
  EXPECT_TRUE(fs::exists(out / "sequence" / "scans" / "000005.pcd"));  // nothing of A's removed
  std::size_t after = 0;
  for ([[maybe_unused]] const auto& e : fs::recursive_directory_iterator(out)) ++after;
  EXPECT_GE(after, before);
  kill(a, SIGTERM);
  int status = 0;
  waitpid(a, &status, 0);
  // Once A has ended, OUT is free again.
  const auto c = test::cli("demo --scans 5 --beams 16 --columns 256 --overwrite --out " + out.string());
  EXPECT_EQ(c.code, 0) << c.output;
}

// A closed terminal or ssh session (issue 45: SIGHUP killed the run, 1000 + 1 here, and left
// no summary).
TEST(OutputPolicy, SighupStopsAtTheNextScanAndExits129) {
  test::TempDir dir;
  const fs::path out = dir / "out";
  EXPECT_EQ(exit_after_signal(out, SIGHUP), 129);
  const auto s = summary(out);
  EXPECT_FALSE(s["complete"].get<bool>());
  EXPECT_NE(s.value("error", "").find("interrupted by SIGHUP"), std::string::npos) << s.dump();
}

TEST(OutputPolicy, ASummaryCutShortByAFullDiskNeverReplacesTheLastOne) {
  // summary.json is written to a .tmp and renamed; a small summary stays in the stream's buffer
  // until it is closed, so the write must fail there, before the rename.
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  test::TempDir dir;
  pipeline::write_summary(dir.path, nlohmann::json{{"command", "run"}}, false, "the first");
  fs::create_symlink("/dev/full", dir / "summary.json.tmp");
  test::expect_error(
      [&] {
        pipeline::write_summary(dir.path, nlohmann::json{{"command", "run"}}, true, "");
      },
      {"summary.json.tmp", "disk full"});
  const auto kept = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_FALSE(kept["complete"].get<bool>());
  EXPECT_EQ(kept["error"], "the first");
}

}  // namespace
}  // namespace cleanmap
