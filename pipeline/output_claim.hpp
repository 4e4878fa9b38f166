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
//
// OUT is held for the whole command by an advisory lock (flock on OUT/.lock, which names the
// holder's process): a second command on a held OUT is refused, naming that process, before
// it touches anything (issue 45: run B's --overwrite emptied OUT while run A wrote there, and A
// reported 100 scans complete beside 85 label files). The lock ends with the returned object
// (or the process).
class OutputLock {
 public:
  OutputLock() = default;
  explicit OutputLock(int fd) : fd_(fd) {}
  OutputLock(OutputLock&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  OutputLock& operator=(OutputLock&& o) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
};
[[nodiscard]] OutputLock claim_output(const OutputRequest& request);

// claim_output, then the command's body. Whatever stops the body (bad input, a failed write,
// Ctrl-C) leaves OUT/summary.json with "complete": false and the message before it reaches main.
// `handle_signals`: SIGINT / SIGTERM stop the body at its next scan (the command line; a
// library's host, such as Python, keeps its own handlers).
void run_guarded(const OutputRequest& request, const std::function<void()>& body, bool handle_signals = true);

}  // namespace cleanmap::pipeline
