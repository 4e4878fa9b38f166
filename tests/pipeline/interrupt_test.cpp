// A signal ends a command even when its scan never reaches the next check (issue 45: SIGTERM
// was ignored while a scan ran, 17 minutes seen, and `timeout` could not end the run).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "pipeline/interrupt.hpp"
#include "pipeline/output_claim.hpp"
#include "tests/test_support.hpp"

namespace cleanmap::pipeline {
namespace {

TEST(Interrupt, ASignalEndsAScanThatNeverChecksForIt) {
  test::TempDir dir;
  const auto out = dir / "out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    try {
      run_guarded({out, "run", {}, false}, [&] {
        std::ofstream(out / "started").put('1');
        for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));  // a scan that never ends
      });
    } catch (...) {
    }
    _exit(0);  // never reached: the watchdog ends the process
  }
  for (int k = 0; k < 1000 && !std::filesystem::exists(out / "started"); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGTERM);
  int status = 0;
  for (int k = 0; k < 3000 && waitpid(pid, &status, WNOHANG) == 0; ++k) {  // at most 30 s
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!WIFEXITED(status) && !WIFSIGNALED(status)) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "the command did not end after SIGTERM";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_FALSE(s["complete"].get<bool>());
  EXPECT_NE(s.value("error", "").find("interrupted by SIGTERM in the middle of a scan"), std::string::npos) << s.dump();
}

}  // namespace
}  // namespace cleanmap::pipeline
