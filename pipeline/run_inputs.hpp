#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "io/sequence.hpp"
#include "odometry/platform_mask.hpp"

namespace cleanmap::pipeline {

// The platform mask, learnt from the first scans in the sensor frame (world-frame inputs, such
// as DynamicMap's, are cleaned already: only the crop box could apply, and it has no frame).
// `read`, when given, receives the first `keep` of the scans it was learnt from, as load_scan
// gave them (index i at i), so that a run need not read them twice.
PlatformMask platform_mask(const Sequence& seq, const PlatformMaskConfig& cfg,
                           std::vector<std::optional<LoadedScan>>* read = nullptr, std::size_t keep = 0);

// Masked points leave the scan before anything sees it; their outputs are label 0 / NaN.
// Returns how many.
std::size_t drop_masked(LoadedScan& loaded, const PlatformMask& mask);

// Per-point labels of `before` for the points `after` kept of it (both know their points'
// places in the input file).
std::vector<std::uint32_t> follow_points(const Scan& before, const std::vector<std::uint32_t>& labels,
                                         const Scan& after);

// A scan with no valid point: one warning line on stderr naming it and why (no points in the
// file, or only NaN / infinite ones), and an entry {scan, reason} for summary.json.
void note_empty(const LoadedScan& loaded, nlohmann::json& empty_scans);

}  // namespace cleanmap::pipeline
