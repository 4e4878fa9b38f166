#pragma once

#include <string>

#include "io/error.hpp"

namespace cleanmap::pipeline {

// Ctrl-C (SIGINT) or SIGTERM during a command: the first one asks the command to stop at the
// next scan (so summary.json can say why it is incomplete); a second one ends the process at once.
struct Interrupted : Error {
  Interrupted(const std::string& message, int sig) : Error(message), signal(sig) {}
  int signal;  // SIGINT or SIGTERM: a command exits 128 + signal, as a shell reports it
};

void install_interrupt_handler();

// Throws Interrupted ("interrupted by SIGINT after <where>") once a signal has arrived.
void throw_if_interrupted(const std::string& where);

}  // namespace cleanmap::pipeline
