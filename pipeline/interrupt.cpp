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
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

void throw_if_interrupted(const std::string& where) {
  const int sig = g_signal.load();
  if (sig == 0) return;
  throw Interrupted(std::string("interrupted by ") + (sig == SIGINT ? "SIGINT (Ctrl-C)" : "SIGTERM") + " after " + where, sig);
}

}  // namespace cleanmap::pipeline
