#include "pipeline/output_claim.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <chrono>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "pipeline/interrupt.hpp"
#include "pipeline/output_dir.hpp"
#include "io/error.hpp"

namespace cleanmap::pipeline {
namespace fs = std::filesystem;
namespace {

// A path for a message: long ones shortened (a 5 KB path would fill the terminal).
std::string shown(const fs::path& p) {
  const std::string s = p.string();
  return s.size() <= 120 ? s : s.substr(0, 60) + "..." + s.substr(s.size() - 40);
}

bool within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

fs::path resolved(const fs::path& p) {
  std::error_code ec;
  const fs::path r = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? fs::absolute(p).lexically_normal() : r;
}

void check_path(const fs::path& out) {
  if (out.empty()) throw Error("--out: empty path (name an output folder)");
  const std::string s = out.string();
  if (s.size() >= PATH_MAX) {
    throw Error("--out: path of " + std::to_string(s.size()) + " characters is too long (the system allows " +
                std::to_string(PATH_MAX - 1) + "): " + shown(out));
  }
  for (const auto& part : out) {
    if (part.string().size() > NAME_MAX) {
      throw Error("--out: a folder name of " + std::to_string(part.string().size()) +
                  " characters is too long (the file system allows " + std::to_string(NAME_MAX) + "): " + shown(out));
    }
  }
}

void check_inputs(const OutputRequest& r) {
  const fs::path out = resolved(r.out);
  for (const auto& input : r.inputs) {
    if (input.empty()) continue;
    const fs::path in = resolved(input);
    if (within(out, in)) {
      fail(r.out, std::string(out == in ? "is" : "lies inside") + " the input " + shown(input) +
                      ": outputs would overwrite the log's files (labels/, poses.txt, times.txt); choose another --out");
    }
    if (within(in, out)) {
      fail(r.out, "contains the input " + shown(input) + ": choose an --out that does not hold the log");
    }
  }
}

constexpr const char* kLockName = ".lock";

// Holds OUT/.lock (created if need be) or refuses, naming the process that holds it. `created`:
// the lock file is new (removed again if the claim is refused).
OutputLock hold(const fs::path& out, bool& created) {
  const fs::path file = out / kLockName;
  std::error_code ec;
  created = !fs::exists(file, ec);
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) fail(out, std::string("cannot create its lock file .lock (") + std::strerror(errno) + ")");
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char holder[64] = {0};
    const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
    ::close(fd);
    std::string who(holder, n > 0 ? static_cast<std::size_t>(n) : 0);
    while (!who.empty() && (who.back() == '\n' || who.back() == ' ')) who.pop_back();
    fail(out, "is in use by another cleanmap command (" + (who.empty() ? std::string("process unknown") : who) +
                  " holds OUT/.lock): wait for it to end, or choose another --out");
  }
  return OutputLock(fd);
}

// Names this process in the held lock file, once OUT is known to be this command's.
void stamp(const fs::path& out, int fd) {
  const std::string me = "pid " + std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size())) {
    fail(out, std::string("cannot write its lock file .lock (") + std::strerror(errno) + ")");
  }
}

// What cleanmap's commands write at the top of OUT (each command's own files and folders, the
// report, the lock, the offline spills). --overwrite removes these and nothing else.
bool written_by_cleanmap(const std::string& name) {
  static const std::set<std::string> names{
      "summary.json", "summary.json.tmp", kLockName, ".offline", "map.bt", "map.ot", "map_2d.pgm", "map_2d.yaml",
      "map_raw.pcd", "map_static.pcd", "map_static.ply", "map_dynamic.pcd", "static.pcd", "dynamic.pcd", "poses.txt",
      "times.txt", "poses_kitti.txt", "poses_tum.txt", "odometry_log.csv", "config.yaml", "labels", "scores", "scans",
      "sequence", "sequences", "run", "with", "without", "report", "report.html", "error_vs_distance.png", "maps.png",
      "per_scan.png", "trajectory.png"};
  return names.count(name) > 0;
}

// Empties an earlier cleanmap output for --overwrite: a folder whose summary.json carries
// cleanmap's marker, holding only what cleanmap writes. Anything else is refused, untouched.
// The lock file, held by this command, stays.
void empty_earlier_output(const OutputRequest& r) {
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(r.out)) entries += e.path().filename() != kLockName;
  if (entries == 0) return;
  if (!r.overwrite) {
    fail(r.out, "is not empty (" + std::to_string(entries) + " entries, from an earlier run?): pass --overwrite to " +
                    "replace an earlier cleanmap output, or choose a new folder");
  }
  bool ours = false;
  try {
    std::ifstream f(r.out / "summary.json");
    ours = f && nlohmann::json::parse(f).contains(kOutputMarker);
  } catch (const std::exception&) {
    ours = false;
  }
  if (!ours) {
    fail(r.out, "is not empty and holds no cleanmap summary.json (with its \"" + std::string(kOutputMarker) +
                    "\" key): --overwrite only replaces an earlier cleanmap output; choose a new folder");
  }
  for (const auto& e : fs::directory_iterator(r.out)) {
    if (!written_by_cleanmap(e.path().filename().string())) {
      fail(r.out, "holds '" + e.path().filename().string() + "', which cleanmap does not write: --overwrite removes "
                  "only cleanmap's outputs, so nothing was removed; move it away or choose a new folder");
    }
  }
  for (const auto& e : fs::directory_iterator(r.out)) {
    if (e.path().filename() == kLockName) continue;
    std::error_code ec;
    fs::remove_all(e.path(), ec);  // a symbolic link goes, never what it points to
    if (ec) fail(e.path(), "cannot remove for --overwrite (" + ec.message() + ")");
  }
}

}  // namespace

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

OutputLock claim_output(const OutputRequest& r) {
  check_path(r.out);
  check_inputs(r);
  std::error_code ec;
  if (fs::exists(r.out, ec) && !fs::is_directory(r.out, ec)) fail(r.out, "exists and is not a folder");
  make_dirs(r.out);
  bool created = false;
  OutputLock lock = hold(r.out, created);
  try {
    empty_earlier_output(r);
  } catch (...) {
    if (created) fs::remove(r.out / kLockName, ec);  // a refused folder is left as it was
    throw;
  }
  stamp(r.out, lock.fd());
  write_summary(r.out, {{"command", r.command}}, false);
  return lock;
}

void run_guarded(const OutputRequest& r, const std::function<void()>& body, bool handle_signals) {
  const OutputLock lock = claim_output(r);
  auto mark = [&r](const std::string& message) {
    nlohmann::json summary{{"command", r.command}};
    try {
      std::ifstream f(r.out / "summary.json");
      if (f) summary = nlohmann::json::parse(f);
    } catch (const std::exception&) {
    }
    try {
      write_summary(r.out, summary, false, message);
    } catch (const std::exception&) {
      // The folder may be what failed (removed, full): the message still reaches main.
    }
  };
  // The command's own stop and the watchdog's (a scan still running a second after a signal)
  // each mark the summary; only the first does.
  auto mark_once = [&](const std::string& message) {
    if (!handle_signals || claim_last_words()) {
      mark(message);
      return;
    }
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));  // the watchdog ends the process
  };
  if (handle_signals) install_interrupt_handler(mark);
  struct Forget {
    bool on;
    ~Forget() {
      if (on) forget_last_words();
    }
  } forget{handle_signals};
  try {
    body();
  } catch (const Error& e) {
    mark_once(e.what());
    throw;
  } catch (const fs::filesystem_error& e) {
    mark_once(describe(e));
    throw Error(describe(e));
  } catch (const std::exception& e) {
    mark_once(std::string("internal error: ") + e.what());
    throw;
  }
}

}  // namespace cleanmap::pipeline
