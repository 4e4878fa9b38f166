#pragma once

#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "dynamics/object_rule.hpp"
#include "dynamics/spatiotemporal_scorer.hpp"

namespace cleanmap {

// Follows objects across scans (TrackRule) so a mover's label holds in the scans where the
// normals miss it (a car seen side-on, a truck crawling, a car waiting at a light). Objects of
// consecutive scans are chained into tracks; an object is moving when its track is seen moving
// within `window` scans of it, before or after. Only a confirmed sighting counts: the track is
// seen moving in two scans between which it moved at least the cluster radius. A static blob
// the scorer calls moving once or twice (the log's last scan, a gust through a hedge) would
// otherwise spread to every scan around it (SemanticKITTI 07: a building patch wrong in scan 9
// spread to scans 7 and 8, IoU 0.44 -> 0.40).
// Takes the scorer's scans in order and returns them `window` scans later (all at finish());
// scans without objects (tracking off in the scorer) pass through unchanged.
// At the log's first and last scan it also marks the points of objects whose track is
// confirmed by sightings from scans with both sides of the window
// (ScoredScan::on_moving_track): there the normals see one side of time only, and a car
// driving alongside looks to the whole log's visibility like something standing (its cells
// are hit by its own body scan after scan); its track, seen moving where the normals had both
// sides, says otherwise.
class ObjectTracker {
 public:
  // `pose_noise` (m) and `pose_noise_deg`: each scan's pose error (1 sigma), for the shift a
  // standing object's points may show between two scans (displacement_floor).
  ObjectTracker(const TrackRule& rule, int window, double margin, double pose_noise = 0.0,
                double pose_noise_deg = 0.0);

  std::vector<ScoredScan> push(ScoredScan scan);
  std::vector<ScoredScan> finish();

 private:
  struct Held {
    ScoredScan scan;
    std::vector<std::size_t> track;  // per object
    std::vector<Eigen::Matrix3Xf> samples;  // per object: up to kSamples of its points
  };
  // A released scan's sightings, for the scans after it to register against.
  struct Past {
    std::size_t scan = 0;
    double stamp = 0.0;
    std::vector<std::size_t> track;
    std::vector<Eigen::Matrix3Xf> samples;
  };
  static constexpr Eigen::Index kSamples = 32;
  struct Sighting {
    std::size_t scan = 0;  // ScoredScan::index
    Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
    bool two_sided = false;  // the scan was scored with both sides of the window
  };
  void chain(Held& now);
  // `two_sided`: only sightings from scans scored with both sides of the window confirm.
  bool moving_near(std::size_t track, std::size_t scan, bool two_sided = false) const;
  // The track was seen moving (by the normals) in a scan within the window of `scan`.
  bool seen_near(std::size_t track, std::size_t scan) const;
  // Object `u` of `held` shifted, by its registered points, beyond what noise explains against
  // the earliest and the latest sighting of its track within the window, the same way.
  bool displaced(const Held& held, std::size_t u) const;
  // The registered shift from `from` to `to` (`seconds` apart, at `range` from the sensor),
  // when the points pair up and it exceeds the noise floor; else none.
  std::optional<Eigen::Vector3f> shift(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to, double seconds,
                                       float range) const;
  ScoredScan release(Held held);

  TrackRule rule_;
  std::size_t window_;
  double margin_;
  double pose_noise_, pose_noise_deg_;
  std::deque<Held> held_;
  std::deque<Past> past_;  // the last `window` scans released
  std::size_t next_track_ = 0;
  std::map<std::size_t, std::vector<Sighting>> seen_moving_;  // per track, oldest first
};

// The one-to-one matches between two scans' objects (index in a, index in b): nearest centroids
// first, each within `gate` of the other and each inside the other's box grown by `gate` (one
// object, not a mover and the wall it merged with).
std::vector<std::pair<std::size_t, std::size_t>> match_objects(const std::vector<ScanObject>& a,
                                                               const std::vector<ScanObject>& b,
                                                               double gate);

}  // namespace cleanmap
