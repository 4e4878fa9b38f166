// What a person sees on a terminal: cleanmap run under a pseudo-terminal (forkpty), its screen
// output read back and taken apart into progress updates ("\r" refreshes) and lines.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

struct Screen {
  int code = -1;
  std::string text;
};

// Runs the cleanmap binary with `args` on a pseudo-terminal (stdout and stderr both), at most
// `limit_s` seconds; `on_read` sees each piece of output as it arrives.
Screen run_on_terminal(const std::vector<std::string>& args,
                       const std::function<void(const std::string&)>& on_read = {}, int limit_s = 300) {
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(CLEANMAP_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(CLEANMAP_BINARY, argv.data());
    _exit(127);
  }
  Screen s;
  if (pid < 0) return s;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(limit_s);
  char buf[4096];
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{master, POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) {
      if (waitpid(pid, nullptr, WNOHANG) == pid) return s;  // exited, nothing more to read
      continue;
    }
    const ssize_t n = read(master, buf, sizeof(buf));
    if (n <= 0) break;  // EIO: the child closed the terminal
    s.text.append(buf, static_cast<std::size_t>(n));
    if (on_read) on_read(std::string(buf, static_cast<std::size_t>(n)));
  }
  kill(pid, SIGKILL);  // only past the limit; otherwise it has exited
  int status = 0;
  waitpid(pid, &status, 0);
  s.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  close(master);
  return s;
}

struct Update {
  std::size_t done, total;
  double rate, eta;
};

// "LABEL  DONE/TOTAL scans  RATE scans/s  ETA ETA s" (trailing blanks allowed), else nothing.
std::optional<Update> parse_update(const std::string& part, std::string& label) {
  const auto scans = part.find(" scans  ");
  if (scans == std::string::npos) return std::nullopt;
  const auto gap = part.rfind("  ", scans);
  if (gap == std::string::npos || gap == 0) return std::nullopt;
  Update u{};
  char tail = 0;
  const int n = std::sscanf(part.c_str() + gap, "  %zu/%zu scans  %lf scans/s  ETA %lf s %c", &u.done, &u.total, &u.rate,
                            &u.eta, &tail);
  if (n != 4) return std::nullopt;
  label = part.substr(0, gap);
  return u;
}

TEST(TerminalProgress, EachPassHasOneHonestBarThatEndsAtItsScansAndTheRunOneRate) {
  test::TempDir dir;
  ASSERT_EQ(test::cli("demo --generate-only --scans 14 --beams 32 --columns 1024 --out " + dir.path.string()).code, 0);
  const Screen s = run_on_terminal({"run", "--input", (dir / "sequence").string(), "--out", (dir / "run").string(),
                                    "--voxel-size", "0.2"});
  ASSERT_EQ(s.code, 0) << s.text;

  // Progress refreshes with "\r" on one line (the terminal turns "\n" into "\r\n"): of each
  // line, every refresh is an update and the last one is what stays on screen.
  std::map<std::string, std::vector<Update>> bars;
  std::vector<std::string> lines;
  std::string text;
  for (std::size_t i = 0; i < s.text.size(); ++i) {
    if (!(s.text[i] == '\r' && i + 1 < s.text.size() && s.text[i + 1] == '\n')) text += s.text[i];
  }
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream refreshes(line);
    std::string part, last;
    while (std::getline(refreshes, part, '\r')) {
      if (part.rfind("\033[K", 0) == 0) part.erase(0, 3);  // the bar cleared before a pass's line
      std::string label;
      if (const auto u = parse_update(part, label)) {
        bars[label].push_back(*u);
      } else if (!part.empty()) {
        last = part;
      }
    }
    if (!last.empty()) lines.push_back(last);
  }
  for (const char* pass : {"run (pass 1 of 2)", "run (rays)", "run (pass 2 of 2)"}) {
    ASSERT_TRUE(bars.count(pass)) << "no bar for " << pass << " in:\n" << s.text;
    const auto& u = bars[pass];
    for (std::size_t k = 0; k < u.size(); ++k) {
      EXPECT_EQ(u[k].total, 14u) << pass;
      if (k > 0) {
        EXPECT_GE(u[k].done, u[k - 1].done) << pass << ": the count went back";
      }
      // The ETA is what is left at the rate so far: the rate is printed to 0.1 scans/s and the
      // ETA to whole seconds, so it lies between what is left at the printed rate +- 0.05.
      if (u[k].rate > 0.05) {
        const double left = static_cast<double>(u[k].total - u[k].done);
        EXPECT_GE(u[k].eta, left / (u[k].rate + 0.05) - 0.5) << pass;
        EXPECT_LE(u[k].eta, left / (u[k].rate - 0.05) + 0.5) << pass;
      }
    }
    EXPECT_EQ(u.back().done, 14u) << pass << ": the bar does not reach its last scan";
    EXPECT_EQ(u.back().eta, 0.0) << pass;
    // The bar is followed by its pass's line, counting the same scans.
    bool closed = false;
    for (const auto& l : lines) closed |= l.rfind(std::string(pass) + ": 14 scans in ", 0) == 0;
    EXPECT_TRUE(closed) << pass << " has no closing line in:\n" << s.text;
  }
  // One rate in what stays on screen (the command's last line), and nothing a library printed.
  std::size_t rates = 0;
  for (const auto& l : lines) {
    rates += l.find("scans/s") != std::string::npos;
    EXPECT_EQ(l.find("Writing"), std::string::npos) << l;
    EXPECT_NE(l, " done.");
  }
  EXPECT_EQ(rates, 1u) << s.text;
}

// The bar counts scans that are finished, not read: whenever it says k of them, the labels of k
// scans are on disk (it used to follow the first stage, a window ahead: "30/30 scans, ETA 0 s"
// while 10 scans were still being scored).
TEST(TerminalProgress, TheBarCountsScansWhoseOutputIsWritten) {
  test::TempDir dir;
  ASSERT_EQ(test::cli("demo --generate-only --scans 16 --beams 32 --columns 1024 --out " + dir.path.string()).code, 0);
  std::size_t updates = 0, ahead = 0;
  std::string report;
  const Screen s = run_on_terminal(
      {"run", "--online", "--input", (dir / "sequence").string(), "--out", (dir / "run").string(), "--voxel-size", "0.2"},
      [&](const std::string& piece) {
        std::size_t said = 0;
        bool any = false;
        for (auto at = piece.find("run  "); at != std::string::npos; at = piece.find("run  ", at + 1)) {
          std::size_t k = 0;
          if (std::sscanf(piece.c_str() + at, "run  %zu/16 scans", &k) == 1) {
            said = k;
            any = true;
          }
        }
        if (!any) return;
        ++updates;
        std::size_t written = 0;
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(dir / "run" / "labels", ec)) {
          written += e.path().extension() == ".label";
        }
        if (written < said) {
          ++ahead;
          report += std::to_string(said) + " said, " + std::to_string(written) + " written; ";
        }
      });
  ASSERT_EQ(s.code, 0) << s.text;
  EXPECT_GE(updates, 1u) << s.text;
  EXPECT_EQ(ahead, 0u) << report;
}

}  // namespace
}  // namespace cleanmap
