// Numeric settings and evaluation inputs out of range (issue 14, defects 10 and 11): one error
// naming the setting (and the preset file), before any work.
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/cloud_file.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {
namespace fs = std::filesystem;

// The command's exit code and output.
test::CliResult run(const std::string& args) { return test::cli(args); }

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

TEST(SettingsCheck, NonFiniteAndOutOfRangeValuesNameTheSetting) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 3 --beams 16 --columns 256 --out " + (dir / "demo").string()).code, 0);
  const std::string log = (dir / "demo" / "sequence").string();
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--voxel-size nan", "--voxel-size: must be a finite number"},
      {"--radius -1", "--radius: must be in [0.001, 100], not -1"},
      // Issue 45: each of these crashed, hung or ran for minutes (keys overflowing int32, 10^17
      // neighbour cells, 2^31 flush items, 30,000 cells per ray, a street-wide cluster search).
      {"--radius 1e-10", "--radius: must be in [0.001, 100], not 1e-10"},
      {"--cell-size 1e-6", "cell_size must be 0 (= radius) or in [radius / 4, 100] m"},
      {"--window-half 1073741823", "--window-half: must be in [1, 1000], not 1073741823"},
      {"--resolution 0.001", "too fine for map_max_range"},
      {"--free-space-cluster-radius 1e308", "cluster radius must be in (0, 10] m"},
      {"--cluster-min-dynamic 0", "--cluster-min-dynamic: must be in [1, 1000000], not 0"},
      {"--map-origin 1e300 0 0", "--map-origin (input.map_origin) takes 3 numbers within 1e8 m"},
      {"--resolution 1e-9", "--resolution: must be in [0.001, 100], not 1e-09"},
      {"--resolution 0.001 --map-max-range 100", "too fine for map_max_range 100 m"},
      {"--window-half 0", "--window-half: must be in [1, 1000], not 0"},
      {"--prob-hit 2", "--prob-hit: must be in (0.5, 1], not 2"},
      {"--occupancy-grid --grid-z-min 3 --grid-z-max 2", "--grid-z-min (mapping.grid_z_min) 3 m must be below --grid-z-max 2 m"}};
  for (const auto& [opt, message] : cases) {
    const auto r = run("run --input " + log + " --out " + (dir / "out").string() + " --overwrite " + opt);
    EXPECT_EQ(r.code, 1) << opt;
    EXPECT_NE(r.output.find(message), std::string::npos) << opt << ": " << r.output;
    EXPECT_LE(lines(r.output), 2u) << opt << ": " << r.output;  // was 19k OctoMap lines for 1e-9
    const auto s = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
    EXPECT_FALSE(s["complete"].get<bool>());
  }
  std::ofstream(dir / "p.yaml") << "scorer:\n  radius: .nan\n";
  auto r = run("score --input " + log + " --out " + (dir / "s").string() + " --config " + (dir / "p.yaml").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("p.yaml: scorer.radius: must be a finite number"), std::string::npos) << r.output;
  // A key that is a map (YAML's "? key"): yaml-cpp's own exception, without the file, before.
  std::ofstream(dir / "k.yaml") << "odometry:\n?  mr_tion: 0.2\n";
  r = run("score --input " + log + " --out " + (dir / "k").string() + " --config " + (dir / "k.yaml").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("k.yaml: line 2: a key must be a plain name"), std::string::npos) << r.output;
  // An empty --input (issue 45: ": no such folder", naming nothing).
  r = run("run --input '' --out " + (dir / "e").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("input: empty path"), std::string::npos) << r.output;
  // An inverted field of view (issue 45: simulated upside down).
  r = run("demo --fov-up-deg -10 --fov-down-deg 10 --out " + (dir / "fov").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("--fov-up-deg (-10.000000) must be above --fov-down-deg"), std::string::npos) << r.output;
  // A typo that would allocate what no sensor produces (1e5 beams: 35 GB of scans before).
  r = run("demo --beams 100000 --out " + (dir / "big").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("--beams: must be in [1, 1024], not 100000"), std::string::npos) << r.output;
}

// --threads 2147483647 asked TBB for 2^31 workers and ended in std::bad_alloc: refused while
// parsing, naming the option and its range.
TEST(SettingsCheck, ThreadsBeyondAnyMachineAreRefusedByName) {
  test::TempDir dir;
  const auto r =
      run("--threads 2147483647 demo --generate-only --scans 2 --out " + (dir / "demo").string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1024"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "demo" / "sequence"));
}

// `cleanmap frobnicate` said only "A subcommand is required": the word is named and the
// commands listed, in one line.
TEST(SettingsCheck, AnUnknownCommandIsNamedAndTheCommandsListed) {
  const auto r = run("--threads 2 frobnicate --out x");
  EXPECT_EQ(r.code, 2);  // the one exit code of usage errors (README: Exit codes)
  EXPECT_NE(r.output.find("'frobnicate' is not a command"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("demo, score, odometry, run"), std::string::npos) << r.output;
  EXPECT_EQ(lines(r.output), 1u) << r.output;
}

// Issue 45: CLI11 read an empty string as 0 (`--radius ''` ran with radius 0), and its parse
// errors exited with 104-114.
TEST(SettingsCheck, AnEmptyNumberIsRefusedAndUsageErrorsExitTwo) {
  test::TempDir dir;
  auto r = run("run --input " + dir.path.string() + " --out " + (dir / "o").string() + " --radius ''");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--radius"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("an empty value is not a number"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "o"));  // refused before OUT is claimed
  EXPECT_EQ(run("run --no-such-option 1").code, 2);
  EXPECT_EQ(run("run --help").code, 0);
}

TEST(SettingsCheck, EvaluationsRefuseWhatTheyCannotMeasure) {
  test::TempDir dir;
  std::ofstream(dir / "one.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream(dir / "two.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n";
  auto r = run("eval trajectory --est " + (dir / "one.txt").string() + " --ref " + (dir / "one.txt").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("one.txt: nothing to measure: 1 pose(s)"), std::string::npos) << r.output;
  r = run("eval trajectory --est " + (dir / "two.txt").string() + " --ref " + (dir / "two.txt").string() + " --delta 2");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("--delta 2 frames is not shorter than the 2 paired poses"), std::string::npos) << r.output;
  EXPECT_NE(run("eval trajectory --est " + (dir / "two.txt").string() + " --ref " + (dir / "two.txt").string() +
                " --delta 0").code, 0);
  Scan gt;
  gt.points = Eigen::Matrix3Xf::Random(3, 4);
  gt.intensity = Eigen::VectorXf::Zero(4);
  write_cloud(dir / "out.pcd", gt);
  gt.intensity[2] = 0.5f;
  write_cloud(dir / "gt.pcd", gt);
  const std::string clouds = " --gt " + (dir / "gt.pcd").string() + " --output " + (dir / "out.pcd").string();
  r = run("eval map" + clouds);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("gt.pcd: point 2 has intensity 0.5: ground truth must be 0 (static) or 1 (dynamic)"),
            std::string::npos) << r.output;
  for (const char* d : {"-1", "nan", "0"}) {
    r = run("eval map" + clouds + " --distance " + d);
    EXPECT_NE(r.code, 0) << d;
    EXPECT_NE(r.output.find("--distance"), std::string::npos) << d << ": " << r.output;
  }
}

TEST(SettingsCheck, OptionsWorkAfterTheSubcommandBooleansAreFlagsAndPresetsRoundTrip) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 3 --beams 16 --columns 256 --out " + (dir / "demo").string()).code, 0);
  const std::string log = (dir / "demo" / "sequence").string();
  // --threads after the subcommand, a --no- flag, a flag with =value, a number.
  auto r = run("run --input " + log + " --out " + (dir / "out").string() +
               " --threads 1 --no-free-space --object-completion=false --radius 0.5 --use-given-poses");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto s = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  EXPECT_FALSE(s["mapping"]["free_space"].get<bool>());
  EXPECT_FALSE(s["scorer"]["object_completion"].get<bool>());
  EXPECT_DOUBLE_EQ(s["scorer"]["radius"].get<double>(), 0.5);
  // The run's own preset gives the same settings back.
  ASSERT_TRUE(fs::exists(dir / "out" / "config.yaml"));
  r = run("config --config " + (dir / "out" / "config.yaml").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("radius: 0.5\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("free_space: false\n"), std::string::npos) << r.output;
  std::ofstream(dir / "p.yaml") << r.output;
  EXPECT_EQ(run("config --config " + (dir / "p.yaml").string()).output, r.output);
  // --help shows defaults.
  r = run("run --help");
  EXPECT_NE(r.output.find("--radius FLOAT=0.3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--free-space,--no-free-space"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[default: on]"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cleanmap
