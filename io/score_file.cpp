#include "io/score_file.hpp"

#include <fstream>
#include <string>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap {

std::vector<float> read_scores(const std::filesystem::path& file, std::size_t expected_points) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read file (" + ec.message() + ")");
  if (bytes % 4 != 0) fail(file, "size is not a multiple of 4 (float32 scores)");
  if (expected_points != 0 && bytes / 4 != expected_points) {
    fail(file, "has " + std::to_string(bytes / 4) + " scores but its scan has " +
                   std::to_string(expected_points) + " points");
  }
  std::vector<float> scores(bytes / 4);
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(scores.data()), static_cast<std::streamsize>(bytes));
  if (!in) fail(file, "short read");
  return scores;
}

void write_scores(const std::filesystem::path& file, const std::vector<float>& scores) {
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file, "cannot create file");
  out.write(reinterpret_cast<const char*>(scores.data()),
            static_cast<std::streamsize>(scores.size() * sizeof(float)));
  close_checked(out, file);
}

}  // namespace cleanmap
