#include "pipeline/run_inputs.hpp"

#include <algorithm>
#include <cstdio>

#include "io/label_file.hpp"

namespace cleanmap::pipeline {

PlatformMask platform_mask(const Sequence& seq, const PlatformMaskConfig& cfg,
                           std::vector<std::optional<LoadedScan>>* read, std::size_t keep) {
  if (seq.world_frame) return {};
  std::vector<Eigen::Matrix3Xf> first;
  const auto n = std::min(seq.size(), static_cast<std::size_t>(cfg.learn_scans));
  for (std::size_t i = 0; cfg.automatic && i < n; ++i) {
    LoadedScan loaded = load_scan(seq, i);
    first.push_back(loaded.scan.points);
    if (read && i < keep) read->emplace_back(std::move(loaded));
  }
  return learn_platform_mask(first, cfg);
}

std::vector<std::uint32_t> follow_points(const Scan& before, const std::vector<std::uint32_t>& labels,
                                         const Scan& after) {
  if (labels.empty() || after.size() == before.size()) return labels;
  const auto by_input = to_input_order(before, labels, kLabelUnscored);
  std::vector<std::uint32_t> out(after.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = by_input[after.input_index.empty() ? i : static_cast<std::size_t>(after.input_index[i])];
  }
  return out;
}

std::size_t drop_masked(LoadedScan& loaded, const PlatformMask& mask) {
  if (mask.empty()) return 0;
  const auto keep = unmasked_points(loaded.scan.points, mask);
  const std::size_t masked = loaded.scan.size() - keep.size();
  if (masked == 0) return 0;
  if (!loaded.labels.empty()) {
    std::vector<std::uint32_t> labels(keep.size());
    for (std::size_t k = 0; k < keep.size(); ++k) labels[k] = loaded.labels[static_cast<std::size_t>(keep[k])];
    loaded.labels = std::move(labels);
  }
  loaded.scan = select_points(loaded.scan, keep);
  return masked;
}

void note_empty(const LoadedScan& loaded, nlohmann::json& empty_scans) {
  const std::size_t n = loaded.scan.input_size;
  const std::string reason =
      n == 0 ? "no points"
             : "all " + std::to_string(n) + " points have NaN or infinite coordinates or lie beyond 1e6 m / 10 s";
  std::fprintf(stderr, "cleanmap: warning: scan %s: %s (scored as empty)\n", loaded.scan.name.c_str(), reason.c_str());
  empty_scans.push_back({{"scan", loaded.scan.name}, {"reason", reason}});
}

}  // namespace cleanmap::pipeline
