#pragma once

#include <charconv>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cleanmap {

// The whole file in memory, read once: the cloud readers check every size a header declares
// against this buffer before they allocate anything for it.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file);

// The next line of `text` from `pos` (without "\n" or "\r\n"), advancing `pos`; nullopt at the end.
std::optional<std::string_view> next_line(std::string_view text, std::size_t& pos);

// Whitespace-separated words of a line.
std::vector<std::string_view> split_words(std::string_view line);

// A whole word as a number ("nan" and "inf" included); nullopt when any of it is not one.
std::optional<double> parse_number(std::string_view word);

// A whole word as a non-negative integer no larger than `max`; nullopt otherwise.
std::optional<std::uint64_t> parse_count(std::string_view word, std::uint64_t max);

// Up to `max` characters of `text` for an error message, bytes outside printable ASCII as '?'
// (a random file's header must not make the message, or summary.json, invalid UTF-8).
std::string printable(std::string_view text, std::size_t max = 40);

}  // namespace cleanmap
