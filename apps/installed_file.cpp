#include "apps/installed_file.hpp"

namespace cleanmap::app {
namespace fs = std::filesystem;

fs::path installed_file(const fs::path& name, const fs::path& in_build) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    fs::path prefix = exe.parent_path();
    const fs::path bindir = CLEANMAP_INSTALL_BINDIR;
    for ([[maybe_unused]] const auto& part : bindir) prefix = prefix.parent_path();
    const fs::path installed = prefix / CLEANMAP_INSTALL_DATA / name;
    if (fs::exists(installed, ec)) return installed;
  }
  return in_build;
}

}  // namespace cleanmap::app
