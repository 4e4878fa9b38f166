#include "apps/output_dir.hpp"

#include <fstream>

#include "io/error.hpp"

namespace cleanmap::app {

void make_dirs(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail(dir, "cannot create output folder (" + ec.message() + ")");
}

void write_summary(const std::filesystem::path& out, nlohmann::json summary, bool complete,
                   const std::string& error) {
  summary["complete"] = complete;
  if (!error.empty()) summary["error"] = error;
  const auto tmp = out / "summary.json.tmp";
  {
    std::ofstream f(tmp);
    if (!f) fail(tmp, "cannot create file");
    f << summary.dump(2) << '\n';
    if (!f) fail(tmp, "write failed");
  }
  std::filesystem::rename(tmp, out / "summary.json");
}

}  // namespace cleanmap::app
