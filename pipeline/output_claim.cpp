#include "pipeline/output_claim.hpp"

#include <climits>
#include <fstream>
#include <nlohmann/json.hpp>

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

// Empties an earlier cleanmap output for --overwrite; refuses folders cleanmap did not write.
void empty_earlier_output(const OutputRequest& r) {
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(r.out)) ++entries;
  if (entries == 0) return;
  if (!r.overwrite) {
    fail(r.out, "is not empty (" + std::to_string(entries) + " entries, from an earlier run?): pass --overwrite to " +
                    "replace an earlier cleanmap output, or choose a new folder");
  }
  bool ours = false;
  try {
    std::ifstream f(r.out / "summary.json");
    ours = f && nlohmann::json::parse(f).contains("command");
  } catch (const std::exception&) {
    ours = false;
  }
  if (!ours) {
    fail(r.out, "is not empty and holds no cleanmap summary.json: --overwrite only replaces an earlier cleanmap "
                "output; choose a new folder");
  }
  for (const auto& e : fs::directory_iterator(r.out)) {
    std::error_code ec;
    fs::remove_all(e.path(), ec);  // a symbolic link goes, never what it points to
    if (ec) fail(e.path(), "cannot remove for --overwrite (" + ec.message() + ")");
  }
}

}  // namespace

void claim_output(const OutputRequest& r) {
  check_path(r.out);
  check_inputs(r);
  std::error_code ec;
  if (fs::exists(r.out, ec) && !fs::is_directory(r.out, ec)) fail(r.out, "exists and is not a folder");
  if (fs::is_directory(r.out, ec)) empty_earlier_output(r);
  make_dirs(r.out);
  write_summary(r.out, {{"command", r.command}}, false);
}

void run_guarded(const OutputRequest& r, const std::function<void()>& body, bool handle_signals) {
  claim_output(r);
  if (handle_signals) install_interrupt_handler();
  auto mark = [&](const std::string& message) {
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
  try {
    body();
  } catch (const Error& e) {
    mark(e.what());
    throw;
  } catch (const std::exception& e) {
    mark(std::string("internal error: ") + e.what());
    throw;
  }
}

}  // namespace cleanmap::pipeline
