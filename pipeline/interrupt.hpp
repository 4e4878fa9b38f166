#pragma once

#include <functional>
#include <mutex>
#include <string>

#include "io/error.hpp"

namespace cleanmap::pipeline {

// Ctrl-C (SIGINT) or SIGTERM during a command: the first one asks the command to stop at the
// next scan (so summary.json can say why it is incomplete); a second one ends the process at once.
struct Interrupted : Error {
  Interrupted(const std::string& message, int sig) : Error(message), signal(sig) {}
  int signal;  // SIGINT or SIGTERM: a command exits 128 + signal, as a shell reports it
};

// `last_words`: what the command leaves if a scan has not ended a second after the signal
// (summary.json marked incomplete); then the process ends with 128 + signal.
void install_interrupt_handler(std::function<void(const std::string&)> last_words = {});

// The command's own stop takes the last words (false: the watchdog has them already).
bool claim_last_words();
// The command has ended: the watchdog has nothing left to say for it.
void forget_last_words();

// Throws Interrupted ("interrupted by SIGINT after <where>") once a signal has arrived.
void throw_if_interrupted(const std::string& where);

}  // namespace cleanmap::pipeline
