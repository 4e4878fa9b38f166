#include "io/file_bytes.hpp"

#include <cmath>
#include <fstream>

#include "io/error.hpp"

namespace cleanmap {

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, "no such file");
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read (" + ec.message() + ")");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open");
  std::vector<std::uint8_t> bytes(size);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) fail(file, "read failed");
  return bytes;
}

std::optional<std::string_view> next_line(std::string_view text, std::size_t& pos) {
  if (pos >= text.size()) return std::nullopt;
  const std::size_t end = text.find('\n', pos);
  std::string_view line = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
  pos = end == std::string_view::npos ? text.size() : end + 1;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

std::optional<double> parse_number(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size() || word.empty()) {
    // from_chars reports values beyond double's range as errors; they are still numbers.
    if (ec == std::errc::result_out_of_range && end == word.data() + word.size()) return v;
    return std::nullopt;
  }
  return v;
}

std::optional<std::uint64_t> parse_count(std::string_view word, std::uint64_t max) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size() || word.empty() || v > max) return std::nullopt;
  return v;
}

std::string printable(std::string_view text, std::size_t max) {
  std::string out;
  for (char c : text.substr(0, max)) out += (c >= 32 && c < 127) ? c : '?';
  if (text.size() > max) out += "...";
  return out;
}

}  // namespace cleanmap
