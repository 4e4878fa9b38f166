#include "pipeline/mos_layout.hpp"

#include <algorithm>
#include <cctype>

#include "io/error.hpp"
#include "io/label_file.hpp"

namespace cleanmap::pipeline {
namespace fs = std::filesystem;
namespace {

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

}  // namespace

fs::path mos_predictions_dir(const fs::path& out, const fs::path& input, const std::string& sequence) {
  std::string id = sequence;
  if (id.empty()) {
    id = fs::absolute(input).lexically_normal().filename().string();
    if (id.empty()) id = fs::absolute(input).lexically_normal().parent_path().filename().string();
    if (!all_digits(id)) {
      fail(input, "--mos-predictions: the folder's name is not a sequence number; give --mos-sequence XX");
    }
  }
  if (!all_digits(id) || id.size() > 4) fail(input, "--mos-sequence '" + id + "': not a sequence number (e.g. 08)");
  id.erase(0, std::min(id.find_first_not_of('0'), id.size() - 1));  // "008" and "8" are 08
  if (id.size() < 2) id.insert(0, 2 - id.size(), '0');
  return out / "sequences" / id / "predictions";
}

fs::path mos_label_file(const fs::path& dir, const Scan& scan, std::size_t index) {
  const bool benchmark_name = scan.name.size() == 6 && all_digits(scan.name);
  return dir / ((benchmark_name ? scan.name : scan_name(index)) + ".label");
}

std::vector<std::uint32_t> mos_labels(const Scan& scan, const std::vector<std::uint8_t>& dynamic) {
  std::vector<std::uint32_t> labels(dynamic.size());
  for (std::size_t i = 0; i < dynamic.size(); ++i) labels[i] = dynamic[i] ? kLabelMoving : kLabelStatic;
  return to_input_order(scan, labels, kLabelStatic);
}

}  // namespace cleanmap::pipeline
