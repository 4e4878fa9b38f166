#include "apps/box_truth_options.hpp"

#include <map>
#include <string>

#include "apps/cli_fields.hpp"

namespace cleanmap::app {
using namespace ::cleanmap::pipeline;

void add_box_truth_options(CLI::App& command, BoxTruthOptions& options) {
  command.add_option("--speed", options.speed, "Boxes faster than this (m/s, world frame) are moving")
      ->check(number_in(kNonNegative))->capture_default_str();
  command.add_option("--speed-window", options.window,
                     "A box's speed over this many seconds (centres: a fitted line, 0 for neighbouring scans)")
      ->check(number_in(kNonNegative))->capture_default_str();
  command.add_option("--box-margin", options.margin, "Boxes grown by this on every side, m")
      ->check(number_in(kNonNegative))->capture_default_str();
  const std::map<std::string, BoxSpeedSource> sources{{"points", BoxSpeedSource::kPoints},
                                                      {"centres", BoxSpeedSource::kCentres}};
  command.add_option("--box-speed", options.source,
                     "What a box's speed is measured on: centres (the hand-drawn box centres) or points (the object's "
                     "own points, registered across the window; centres where they cannot be)")
      ->transform(CLI::CheckedTransformer(sources))
      ->default_str("centres");
  const std::map<std::string, bool> moving{{"scan", false}, {"track", true}};
  command.add_option("--box-moving", options.whole_track,
                     "When a box is moving: scan (while its object moves) or track (in every scan, once its object "
                     "moved in any)")
      ->transform(CLI::CheckedTransformer(moving))
      ->default_str("scan");
  command.add_flag("--time-from-azimuth", options.time_from_azimuth,
                   "Raw sweeps without per-point time: place each point with the pose at its time from azimuth");
  const std::map<std::string, double> reference{{"start", 0.0}, {"middle", 0.5}, {"end", 1.0}};
  command.add_option("--pose-reference", options.pose_reference,
                     "Where in its sweep each pose sits, as the run that wrote the poses (deskew_reference): "
                     "start, middle, end")
      ->transform(CLI::CheckedTransformer(reference))
      ->default_str("middle");
}

}  // namespace cleanmap::app
