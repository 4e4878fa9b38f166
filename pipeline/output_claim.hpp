#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace cleanmap::pipeline {

// What a command writes to and what it must never harm.
struct OutputRequest {
  std::filesystem::path out;
  std::string command;
  std::vector<std::filesystem::path> inputs;  // empty paths are skipped
  bool overwrite = false;
};

// Makes OUT this command's, or refuses without touching anything: an empty or over-long path;
// OUT equal to, inside or around an input (outputs would overwrite labels/, poses.txt,
// times.txt of the log, or --overwrite would remove it); OUT not empty without --overwrite. With
// --overwrite an earlier cleanmap output (it has a summary.json) is emptied first, so no file
// of the earlier run stays beside the new summary; any other non-empty folder is refused.
// Then OUT exists and holds summary.json with "complete": false.
void claim_output(const OutputRequest& request);

// claim_output, then the command's body. Whatever stops the body (bad input, a failed write,
// Ctrl-C) leaves OUT/summary.json with "complete": false and the message before it reaches main.
// `handle_signals`: SIGINT / SIGTERM stop the body at its next scan (the command line; a
// library's host, such as Python, keeps its own handlers).
void run_guarded(const OutputRequest& request, const std::function<void()>& body, bool handle_signals = true);

}  // namespace cleanmap::pipeline
