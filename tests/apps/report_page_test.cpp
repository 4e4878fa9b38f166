// `cleanmap report`: the page's content, what it leaves out and why, and (scripts/check-report.sh
// in headless Chromium) what a person sees of it.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

test::CliResult run(const std::string& args) { return test::cli(args); }

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST(CliReport, WritesASelfContainedPageWithPlotsTablesAndA3DView) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 6 --beams 32 --columns 512 --out " + dir.path.string()).code, 0);
  const auto r = run("report " + (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string page = read_text(dir / "run" / "report.html");
  EXPECT_EQ(count(page, "data:image/png;base64,"), 4u);
  for (const char* remote : {"src=\"http", "href=\"http", "url(http", "fetch("}) {
    EXPECT_EQ(page.find(remote), std::string::npos) << remote;  // nothing fetched from a network
  }
  EXPECT_NE(page.find("APE (SE3) translation"), std::string::npos);
  for (const char* png : {"trajectory.png", "error_vs_distance.png", "per_scan.png", "maps.png"}) {
    EXPECT_GT(std::filesystem::file_size(dir / "run" / "report" / png), 5000u) << png;
  }
  // The 3D view: its container, the three clouds, and three.js inlined.
  EXPECT_NE(page.find("<div id=\"map3d\">"), std::string::npos);
  for (const char* block : {"id=\"cloud-static\"", "id=\"cloud-dynamic\"", "id=\"cloud-trajectory\""}) {
    EXPECT_NE(page.find(block), std::string::npos) << block;
  }
  EXPECT_NE(page.find("WebGLRenderer"), std::string::npos);
  // Rounded to what the numbers mean: no fraction with more than 3 significant digits
  // (0.014431431757391469 was printed once; 0.00884 m, 8.84 mm, is as it should be).
  for (auto at = page.find("<td>"); at != std::string::npos; at = page.find("<td>", at + 1)) {
    const std::string cell = page.substr(at + 4, page.find("</td>", at) - at - 4);
    if (cell.find('.') == std::string::npos || cell.find_first_not_of("-0123456789.,") != std::string::npos) continue;
    std::string digits;
    for (const char c : cell) {
      if (c >= '0' && c <= '9' && (c != '0' || !digits.empty())) digits += c;
    }
    EXPECT_LE(digits.size(), 3u) << cell;
  }
  EXPECT_NE(page.find("<td>0.0"), std::string::npos);  // the errors are there, a few cm
  // A 5 m log has no 100 m segment: one line says so instead of a table of n/a.
  EXPECT_NE(page.find("KITTI segment errors</b>: not shown, they need segments of 100 m"), std::string::npos);
  // The text, without the plots' base64 (which may spell n/a by chance) or the scripts.
  std::string text = page.substr(0, page.find("<script"));
  for (auto at = text.find("base64,"); at != std::string::npos; at = text.find("base64,", at)) {
    text.erase(at, text.find('"', at) - at);
  }
  EXPECT_EQ(text.find("n/a"), std::string::npos);
  // Nothing left behind but the page and its plots.
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "report" / "data.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "report" / ".data.json"));
}

TEST(CliReport, WithoutReferencePosesTheErrorPlotIsLeftOutWithItsReason) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 4 --beams 16 --columns 256 --out " + dir.path.string()).code, 0);
  std::filesystem::remove(dir / "sequence" / "poses.txt");  // the reference report looks for
  const auto r = run("report " + (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string page = read_text(dir / "run" / "report.html");
  EXPECT_EQ(count(page, "data:image/png;base64,"), 3u);  // no empty error frame
  EXPECT_NE(page.find("Error vs distance</b>: not shown, there are no reference poses"), std::string::npos);
  EXPECT_EQ(page.find("KITTI segment errors"), std::string::npos);
  EXPECT_EQ(page.find("APE (SE3)"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "report" / "error_vs_distance.png"));
}

TEST(CliReport, ARunOnGivenPosesHasNoEmptyTrajectoryFrame) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --generate-only --scans 4 --beams 16 --columns 256 --out " + dir.path.string()).code, 0);
  ASSERT_EQ(run("run --input " + (dir / "sequence").string() + " --out " + (dir / "run").string() +
                " --use-given-poses").code, 0);
  const auto r = run("report " + (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string page = read_text(dir / "run" / "report.html");
  EXPECT_EQ(count(page, "data:image/png;base64,"), 2u);  // the map and the per-scan plot
  EXPECT_NE(page.find("Trajectory</b>: not shown, this run wrote no poses"), std::string::npos);
  EXPECT_EQ(page.find("Error vs distance"), std::string::npos);  // nothing to say without an estimate
}

TEST(CliReport, WithoutTheViewerScriptThePageSaysWhyItHasNo3DView) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 3 --beams 16 --columns 256 --out " + dir.path.string()).code, 0);
  const auto r = run("report " + (dir / "run").string() + " --viewer " + (dir / "no-such-viewer.js").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string page = read_text(dir / "run" / "report.html");
  EXPECT_EQ(page.find("id=\"map3d\""), std::string::npos);
  EXPECT_NE(page.find("Interactive 3D view</b>: not shown, its script was not built"), std::string::npos);
}

// The page as Chromium draws it at 1280 px: every plot inside the window, nothing cut off below,
// the 3D view's canvas drawn (scripts/check-report.sh; CI installs chromium and playwright-core).
TEST(CliReport, ThePageRendersWholeInChromiumWithItsDrawn3DView) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 6 --beams 32 --columns 512 --out " + dir.path.string()).code, 0);
  ASSERT_EQ(run("report " + (dir / "run").string()).code, 0);
  std::string output;
  const std::string cmd = "bash " + (test::source_dir() / "scripts" / "check-report.sh").string() + " " +
                          (dir / "run").string() + " 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof(buf), p)) output += buf;
  ASSERT_EQ(WEXITSTATUS(pclose(p)), 0) << output;
  EXPECT_NE(output.find("3D view drew"), std::string::npos) << output;
  EXPECT_GT(std::filesystem::file_size(dir / "run" / "report" / "screenshot.png"), 50000u);
}

TEST(CliReport, AFailedRunSaysSoAtTheTopAndACorruptSummaryIsNamed) {
  test::TempDir dir;
  ASSERT_EQ(run("demo --scans 4 --beams 16 --columns 256 --out " + dir.path.string()).code, 0);
  // The run's summary as a failure leaves it, and its static map cut short.
  auto s = nlohmann::json::parse(std::ifstream(dir / "run" / "summary.json"));
  s["complete"] = false;
  s["error"] = "interrupted by SIGINT (Ctrl-C) after 3 of 4 scans (run)";
  std::ofstream(dir / "run" / "summary.json") << s.dump();
  std::filesystem::resize_file(dir / "run" / "map_static.pcd", 300);
  auto r = run("report " + (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("describes an incomplete run"), std::string::npos) << r.output;
  const std::string page = read_text(dir / "run" / "report.html");
  const auto banner = page.find("This run did not complete.");
  ASSERT_NE(banner, std::string::npos);
  EXPECT_LT(banner, page.find("<h2>"));  // above every table
  EXPECT_NE(page.find("after 3 of 4 scans"), std::string::npos);
  EXPECT_NE(page.find("map_static.pcd: WIDTH"), std::string::npos);  // named among the problems
  std::ofstream(dir / "run" / "summary.json") << "{\"command\": \"run\", \"compl";
  r = run("report " + (dir / "run").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("summary.json: is not valid JSON"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cleanmap
