#include "dynamics/object_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "dynamics/track_displacement.hpp"

namespace cleanmap {
namespace {

// `inner` lies inside `outer`'s box grown by `grow` on every side.
bool inside(const ScanObject& inner, const ScanObject& outer, float grow) {
  return (inner.lo.array() >= outer.lo.array() - grow).all() &&
         (inner.hi.array() <= outer.hi.array() + grow).all();
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> match_objects(const std::vector<ScanObject>& a,
                                                               const std::vector<ScanObject>& b,
                                                               double gate) {
  std::vector<std::tuple<float, std::size_t, std::size_t>> near;
  const auto g = static_cast<float>(gate);
  // b by centroid x: each object of a scans only the slice within the gate (a street scan
  // holds a thousand objects, and all pairs cost 2.5 ms per scan).
  std::vector<std::pair<float, std::size_t>> by_x(b.size());
  for (std::size_t j = 0; j < b.size(); ++j) by_x[j] = {b[j].centroid.x(), j};
  std::sort(by_x.begin(), by_x.end());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const float x = a[i].centroid.x();
    auto it = std::lower_bound(by_x.begin(), by_x.end(), std::make_pair(x - g, std::size_t{0}));
    for (; it != by_x.end() && it->first <= x + g; ++it) {
      const std::size_t j = it->second;
      const float d = (a[i].centroid - b[j].centroid).squaredNorm();
      if (d <= g * g && inside(a[i], b[j], g) && inside(b[j], a[i], g)) near.emplace_back(d, i, j);
    }
  }
  std::sort(near.begin(), near.end());
  std::vector<std::uint8_t> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& [d, i, j] : near) {
    if (used_a[i] || used_b[j]) continue;
    used_a[i] = used_b[j] = 1;
    out.emplace_back(i, j);
  }
  return out;
}

ObjectTracker::ObjectTracker(const TrackRule& rule, int window, double margin, double pose_noise,
                             double pose_noise_deg)
    : rule_(rule),
      window_(static_cast<std::size_t>(std::max(window, 0))),
      margin_(margin),
      pose_noise_(pose_noise),
      pose_noise_deg_(pose_noise_deg) {}

// Each object continues the track of its match in the previous scan, or starts one.
void ObjectTracker::chain(Held& now) {
  const auto& objects = now.scan.objects.objects;
  now.track.assign(objects.size(), 0);
  std::vector<std::uint8_t> continued(objects.size(), 0);
  if (!held_.empty() && held_.back().scan.index + 1 == now.scan.index) {
    const Held& before = held_.back();
    const double gap = std::abs(now.scan.scan.stamp - before.scan.scan.stamp);
    for (const auto& [i, j] : match_objects(before.scan.objects.objects, objects, rule_.max_speed * gap + margin_)) {
      now.track[j] = before.track[i];
      continued[j] = 1;
    }
  }
  // Up to kSamples points of each object, spread over its points in scan order.
  const auto& of = now.scan.objects.of_point;
  std::vector<std::size_t> count(objects.size(), 0), seen(objects.size(), 0);
  for (const auto u : of) {
    if (u >= 0) ++count[static_cast<std::size_t>(u)];
  }
  // An object list without its points (hand-made tests) has no samples, so no shifts.
  const bool has_points = static_cast<Eigen::Index>(of.size()) == now.scan.scan.points.cols();
  now.samples.resize(objects.size());
  for (std::size_t u = 0; u < objects.size(); ++u) {
    now.samples[u].resize(3, has_points ? std::min<Eigen::Index>(kSamples, static_cast<Eigen::Index>(count[u])) : 0);
  }
  for (std::size_t k = 0; has_points && k < of.size(); ++k) {
    if (of[k] < 0) continue;
    const auto u = static_cast<std::size_t>(of[k]);
    const std::size_t stride = std::max<std::size_t>(1, count[u] / static_cast<std::size_t>(kSamples));
    const std::size_t n = seen[u]++;
    if (n % stride != 0 || static_cast<Eigen::Index>(n / stride) >= now.samples[u].cols()) continue;
    now.samples[u].col(static_cast<Eigen::Index>(n / stride)) = now.scan.scan.points.col(static_cast<Eigen::Index>(k));
  }
  for (std::size_t j = 0; j < objects.size(); ++j) {
    if (!continued[j]) now.track[j] = next_track_++;
    if (objects[j].seen_moving) {
      const bool two_sided = now.scan.scans_before > 0 && now.scan.scans_after > 0;
      seen_moving_[now.track[j]].push_back({now.scan.index, objects[j].centroid, two_sided});
    }
  }
}

// Confirmed sightings: seen moving in two scans within the window, having moved at least the
// cluster radius between them. A cluster's centroid jitters by up to its linking distance as
// points join and leave (static vegetation seen moving on SemanticKITTI 01: 0.35 m at any gap;
// a walker on 07: 0.15 m per scan, growing with the gap).
bool ObjectTracker::moving_near(std::size_t track, std::size_t scan, bool two_sided) const {
  const auto it = seen_moving_.find(track);
  if (it == seen_moving_.end()) return false;
  const auto& s = it->second;
  const auto far = [&](std::size_t a, std::size_t b) { return (a > b ? a - b : b - a) > window_; };
  for (std::size_t a = 0; a < s.size(); ++a) {
    if (far(s[a].scan, scan) || (two_sided && !s[a].two_sided)) continue;
    for (std::size_t b = 0; b < s.size(); ++b) {
      if (two_sided && !s[b].two_sided) continue;
      if (!far(s[a].scan, s[b].scan) && (s[a].centroid - s[b].centroid).norm() >= margin_) return true;
    }
  }
  return false;
}

bool ObjectTracker::seen_near(std::size_t track, std::size_t scan) const {
  const auto it = seen_moving_.find(track);
  if (it == seen_moving_.end()) return false;
  for (const Sighting& s : it->second) {
    if ((s.scan > scan ? s.scan - scan : scan - s.scan) <= window_) return true;
  }
  return false;
}

std::optional<Eigen::Vector3f> ObjectTracker::shift(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to,
                                                    double seconds, float range) const {
  // Half the cluster radius: pairs within it after the shift are the same surface, and a
  // shift of more than a cluster radius is the centroid rule's (moving_near).
  const auto reach = static_cast<float>(0.5 * margin_);
  // Half of each sample paired: the same object, not a cluster that merged or split.
  constexpr float kOverlap = 0.5f;
  const Shift s = register_shift(from, to, reach);
  const float by = s.by.norm();
  if (s.overlap >= kOverlap && by > displacement_floor(range, pose_noise_, pose_noise_deg_) &&
      by <= static_cast<float>(rule_.max_speed * seconds + margin_)) {
    return s.by;
  }
  return std::nullopt;
}

// Registered against the track's earliest sighting within the window and its latest, the
// object moved beyond the noise floor on both sides, and the same way (the shifts within 60
// degrees): a mover goes on, while the shifts that sampling lends a standing object (the rings
// land elsewhere on it from a new viewpoint) point anywhere. Where the window has one side
// (the log's ends), there is no such evidence.
bool ObjectTracker::displaced(const Held& held, std::size_t u) const {
  const Eigen::Matrix3Xf& own = held.samples[u];
  if (own.cols() < 8) return false;  // too few points to register
  const std::size_t track = held.track[u], index = held.scan.index;
  Eigen::Vector3f sensor = Eigen::Vector3f::Zero();
  if (held.scan.scan.pose) sensor = held.scan.scan.pose->translation().cast<float>();
  const float range = (held.scan.objects.objects[u].centroid - sensor).norm();
  const auto sample_of = [&](const std::vector<std::size_t>& tracks,
                             const std::vector<Eigen::Matrix3Xf>& samples) -> const Eigen::Matrix3Xf* {
    for (std::size_t v = 0; v < tracks.size(); ++v) {
      if (tracks[v] == track) return samples[v].cols() >= 8 ? &samples[v] : nullptr;
    }
    return nullptr;
  };
  std::optional<Eigen::Vector3f> before, after;
  for (const Past& p : past_) {
    if (p.scan + window_ < index) continue;
    if (const auto* earlier = sample_of(p.track, p.samples)) {
      before = shift(*earlier, own, std::abs(held.scan.scan.stamp - p.stamp), range);
      break;
    }
  }
  if (!before) return false;
  for (auto it = held_.rbegin(); it != held_.rend(); ++it) {
    if (it->scan.index <= index || it->scan.index > index + window_) continue;
    if (const auto* later = sample_of(it->track, it->samples)) {
      after = shift(own, *later, std::abs(it->scan.scan.stamp - held.scan.scan.stamp), range);
      break;
    }
  }
  return after && before->dot(*after) > 0.5f * before->norm() * after->norm();
}

ScoredScan ObjectTracker::release(Held held) {
  ScoredScan& s = held.scan;
  const auto& objects = s.objects.objects;
  std::vector<std::uint8_t> moving(objects.size(), 0);
  for (std::size_t u = 0; u < objects.size(); ++u) {
    moving[u] = !objects[u].seen_moving && (moving_near(held.track[u], s.index) ||
                                             (seen_near(held.track[u], s.index) && displaced(held, u)));
  }
  const auto& of = s.objects.of_point;
  for (std::size_t k = 0; k < of.size(); ++k) {
    if (of[k] < 0 || s.dynamic[k] || !moving[static_cast<std::size_t>(of[k])]) continue;
    s.dynamic[k] = 1;
    ++s.tracked_points;
  }
  if (s.scans_before == 0 || s.scans_after == 0) {
    std::vector<std::uint8_t> confirmed(objects.size(), 0);
    bool any = false;
    for (std::size_t u = 0; u < objects.size(); ++u) {
      confirmed[u] = moving_near(held.track[u], s.index, true) ? 1 : 0;
      any |= confirmed[u] != 0;
    }
    if (any) {
      s.on_moving_track.assign(of.size(), 0);
      for (std::size_t k = 0; k < of.size(); ++k) {
        if (of[k] >= 0) s.on_moving_track[k] = confirmed[static_cast<std::size_t>(of[k])];
      }
    }
  }
  // Sightings more than two windows back can neither confirm nor label a held scan any more.
  for (auto it = seen_moving_.begin(); it != seen_moving_.end();) {
    auto& v = it->second;
    while (!v.empty() && v.front().scan + 2 * window_ < s.index) v.erase(v.begin());
    it = v.empty() ? seen_moving_.erase(it) : std::next(it);
  }
  past_.push_back({s.index, s.scan.stamp, std::move(held.track), std::move(held.samples)});
  while (!past_.empty() && past_.front().scan + window_ < s.index + 1) past_.pop_front();
  return std::move(held.scan);
}

std::vector<ScoredScan> ObjectTracker::push(ScoredScan scan) {
  std::vector<ScoredScan> out;
  if (!rule_.enabled) {
    out.push_back(std::move(scan));
    return out;
  }
  Held now{std::move(scan), {}, {}};
  chain(now);
  held_.push_back(std::move(now));
  // A scan is final once the `window` scans after it are in.
  while (held_.size() > window_ + 1) {
    out.push_back(release(std::move(held_.front())));
    held_.pop_front();
  }
  return out;
}

std::vector<ScoredScan> ObjectTracker::finish() {
  std::vector<ScoredScan> out;
  for (auto& h : held_) out.push_back(release(std::move(h)));
  held_.clear();
  return out;
}

}  // namespace cleanmap
