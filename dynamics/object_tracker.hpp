#pragma once

#include <deque>
#include <map>
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
  ObjectTracker(const TrackRule& rule, int window, double margin);

  std::vector<ScoredScan> push(ScoredScan scan);
  std::vector<ScoredScan> finish();

 private:
  struct Held {
    ScoredScan scan;
    std::vector<std::size_t> track;  // per object
  };
  struct Sighting {
    std::size_t scan = 0;  // ScoredScan::index
    Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
    bool two_sided = false;  // the scan was scored with both sides of the window
  };
  void chain(Held& now);
  // `two_sided`: only sightings from scans scored with both sides of the window confirm.
  bool moving_near(std::size_t track, std::size_t scan, bool two_sided = false) const;
  ScoredScan release(Held held);

  TrackRule rule_;
  std::size_t window_;
  double margin_;
  std::deque<Held> held_;
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
