#include "pipeline/interrupt.hpp"

#include <atomic>
#include <csignal>

namespace cleanmap::pipeline {
namespace {

std::atomic<int> g_signal{0};

extern "C" void on_signal(int sig) {
  if (g_signal.exchange(sig) != 0) {
    std::signal(sig, SIG_DFL);  // the second one: stop now
    std::raise(sig);
  }
}

}  // namespace

void install_interrupt_handler() {
  // SIGHUP: a closed terminal or ssh session (issue 45: it killed the run without a summary).
  // A signal the run was started ignoring stays ignored: `nohup cleanmap run ...` must outlive
  // its terminal, and a background job of a script ignores SIGINT.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    if (std::signal(sig, on_signal) == SIG_IGN) std::signal(sig, SIG_IGN);
  }
}

void throw_if_interrupted(const std::string& where) {
  const int sig = g_signal.load();
  if (sig == 0) return;
  const char* name = sig == SIGINT ? "SIGINT (Ctrl-C)" : sig == SIGHUP ? "SIGHUP (the terminal closed)" : "SIGTERM";
  throw Interrupted(std::string("interrupted by ") + name + " after " + where, sig);
}

}  // namespace cleanmap::pipeline
