#include "io/label_file.hpp"

#include <fstream>
#include <string>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap {

std::vector<std::uint32_t> read_labels(const std::filesystem::path& file,
                                       std::optional<std::size_t> expected_points) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read file (" + ec.message() + ")");
  if (bytes % 4 != 0) {
    fail(file, "size " + std::to_string(bytes) + " bytes is not a multiple of 4 (uint32 labels)");
  }
  const std::size_t n = bytes / 4;
  if (expected_points && n != *expected_points) {
    fail(file, "has " + std::to_string(n) + " labels but its scan has " +
                   std::to_string(*expected_points) + " points");
  }
  std::vector<std::uint32_t> labels(n);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open file");
  in.read(reinterpret_cast<char*>(labels.data()), static_cast<std::streamsize>(bytes));
  if (in.gcount() != static_cast<std::streamsize>(bytes)) fail(file, "short read");
  return labels;
}

void write_labels(const std::filesystem::path& file, const std::vector<std::uint32_t>& labels) {
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file, "cannot create file");
  out.write(reinterpret_cast<const char*>(labels.data()),
            static_cast<std::streamsize>(labels.size() * sizeof(std::uint32_t)));
  close_checked(out, file);
}

}  // namespace cleanmap
