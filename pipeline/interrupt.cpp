#include "pipeline/interrupt.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

namespace cleanmap::pipeline {
namespace {

std::atomic<int> g_signal{0};
// Whoever stops the command first (its own Interrupted, or the watchdog) writes its last words.
std::atomic<bool> g_stopping{false};
// Never destroyed: the watchdog thread may still read it while the process exits. Set, reset
// and called under the mutex.
auto* g_last_words = new std::function<void(const std::string&)>();
auto* g_last_words_mutex = new std::mutex();

extern "C" void on_signal(int sig) {
  if (g_signal.exchange(sig) != 0) {
    std::signal(sig, SIG_DFL);  // the second one: stop now
    std::raise(sig);
  }
}

const char* signal_name(int sig) {
  return sig == SIGINT ? "SIGINT (Ctrl-C)" : sig == SIGHUP ? "SIGHUP (the terminal closed)" : "SIGTERM";
}

// A command stops at its next scan; one scan can take long (issue 45: a hostile option kept a
// scan running for 17 minutes, and `timeout` could not end the run). A second after the signal
// the watchdog writes the command's last words (an incomplete summary.json) and ends the
// process as the command would have.
void watch() {
  using namespace std::chrono_literals;
  while (g_signal.load() == 0) std::this_thread::sleep_for(20ms);
  std::this_thread::sleep_for(1s);
  if (g_stopping.exchange(true)) return;  // the command is saying its own last words
  const int sig = g_signal.load();
  const std::string message = std::string("interrupted by ") + signal_name(sig) +
                              " in the middle of a scan (it had not ended a second later)";
  {
    std::lock_guard<std::mutex> lock(*g_last_words_mutex);
    if (*g_last_words) (*g_last_words)(message);
  }
  std::fprintf(stderr, "\ncleanmap: %s\n", message.c_str());
  std::fflush(stderr);
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handler(std::function<void(const std::string&)> last_words) {
  // SIGHUP: a closed terminal or ssh session (issue 45: it killed the run without a summary).
  // A signal the run was started ignoring stays ignored: `nohup cleanmap run ...` must outlive
  // its terminal, and a background job of a script ignores SIGINT.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    if (std::signal(sig, on_signal) == SIG_IGN) std::signal(sig, SIG_IGN);
  }
  {
    std::lock_guard<std::mutex> lock(*g_last_words_mutex);
    *g_last_words = std::move(last_words);
  }
  static std::once_flag started;
  std::call_once(started, [] { std::thread(watch).detach(); });
}

bool claim_last_words() { return !g_stopping.exchange(true); }

void forget_last_words() {
  std::lock_guard<std::mutex> lock(*g_last_words_mutex);
  *g_last_words = {};
}

void throw_if_interrupted(const std::string& where) {
  const int sig = g_signal.load();
  if (sig == 0) return;
  throw Interrupted(std::string("interrupted by ") + signal_name(sig) + " after " + where, sig);
}

}  // namespace cleanmap::pipeline
