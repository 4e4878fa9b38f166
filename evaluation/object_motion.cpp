#include "evaluation/object_motion.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "geometry/point_index.hpp"
#include "odometry/deskew.hpp"

namespace cleanmap {

std::vector<Eigen::Matrix3Xf> points_in_boxes(const Eigen::Matrix3Xf& sensor, const Eigen::Matrix3Xf& world,
                                              const std::vector<LabelBox>& boxes, double margin,
                                              double ground_band) {
  std::vector<Eigen::Matrix3Xf> out;
  out.reserve(boxes.size());
  for (const auto& b : boxes) {
    const GrownBox box(b, margin);
    const double floor = -box.half.z() + ground_band;
    std::vector<Eigen::Index> inside;
    for (Eigen::Index i = 0; i < sensor.cols(); ++i) {
      const Eigen::Vector3d q = box.local(sensor.col(i));
      if (box.contains(q) && q.z() > floor) inside.push_back(i);
    }
    out.emplace_back(world(Eigen::all, inside));
  }
  return out;
}

namespace {

// At most this many points of `from` take part: the shift of a whole truck is as well fixed by
// 2000 of its points as by 40,000, at a twentieth of the nearest-neighbour searches.
constexpr Eigen::Index kMaxFromPoints = 2000;
constexpr int kMaxSteps = 40;
// Pairs count while closer than a reach that starts at 1 m (twice a hand-drawn box's worst
// jitter, so the guess's error is within it) and shrinks by a fifth a step to 0.1 m, where
// what a point's sampling and range noise give stays in.
constexpr double kFirstReach = 1.0;  // m
constexpr double kReachShrink = 0.8;
constexpr double kMinReach = 0.1;    // m
constexpr double kConverged = 1e-5;  // m
// The two starts end this far apart with fits this alike: the points do not tell the shift.
constexpr double kAgree = 0.1;     // m
constexpr double kSameFit = 0.01;  // m
// A target point's surface normal from its neighbours within this radius (at least 5 of
// them): the plane of a truck's side, not the few cm between two scan lines.
constexpr float kNormalRadius = 0.3f;  // m
constexpr std::size_t kMinNormalPoints = 5;

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Unit normals of `to`'s points (zero where too few neighbours give one).
std::vector<Eigen::Vector3d> normals_of(const Eigen::Matrix3Xf& to, const PointIndex& index) {
  std::vector<Eigen::Vector3d> normals(static_cast<std::size_t>(to.cols()), Eigen::Vector3d::Zero());
  tbb::parallel_for(Eigen::Index{0}, to.cols(), [&](Eigen::Index i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    std::size_t n = 0;
    index.for_each_within(to.col(i), kNormalRadius, [&](std::uint32_t j, float) {
      const Eigen::Vector3d q = to.col(static_cast<Eigen::Index>(j)).cast<double>();
      sum += q;
      outer += q * q.transpose();
      ++n;
    });
    if (n < kMinNormalPoints) return;
    const Eigen::Vector3d mean = sum / static_cast<double>(n);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(outer / static_cast<double>(n) - mean * mean.transpose());
    normals[static_cast<std::size_t>(i)] = eig.eigenvectors().col(0);
  });
  return normals;
}

// Point-to-plane steps in the horizontal: each fixes the shift along the normals of the
// surfaces it pairs with, so a truck's side fixes the across and its rear the along at once.
// Point-to-point steps moved along a side only by what its rear's fifth of the points pulled,
// and stopped 0.3 m short.
ObjectShift icp_from(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to, const PointIndex& index,
                     const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& start) {
  ObjectShift s;
  s.translation = start;
  const auto n = static_cast<std::size_t>(from.cols());
  std::vector<double> dist(n);
  std::vector<std::uint32_t> pair(n);
  bool converged = false;
  for (int step = 0;; ++step) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = from.col(static_cast<Eigen::Index>(i)).cast<double>() + s.translation;
      const auto nn = index.nearest(p.cast<float>());
      pair[i] = nn->first;
      dist[i] = std::sqrt(static_cast<double>(nn->second));
    }
    s.residual = median(dist);  // at the current shift: the pairing after the last move
    if (converged || step == kMaxSteps) break;
    const double reach = std::max(kMinReach, kFirstReach * std::pow(kReachShrink, step));
    Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& normal = normals[pair[i]];
      if (dist[i] > reach || normal.isZero()) continue;
      const Eigen::Vector3d p = from.col(static_cast<Eigen::Index>(i)).cast<double>() + s.translation;
      const Eigen::Vector3d q = to.col(static_cast<Eigen::Index>(pair[i])).cast<double>();
      const Eigen::Vector2d horizontal = normal.head<2>();
      a += horizontal * horizontal.transpose();
      b += horizontal * normal.dot(q - p);
    }
    // A direction no surface constrains (a lone wall's along) keeps its shift: the small
    // ridge only makes the solve well posed.
    a += Eigen::Matrix2d::Identity() * (1e-6 * (a.trace() + 1e-9));
    const Eigen::Vector2d move = a.ldlt().solve(b);
    s.translation.head<2>() += move;
    converged = move.norm() < kConverged && reach == kMinReach;
  }
  return s;
}

}  // namespace

std::optional<ObjectShift> register_object(const Eigen::Matrix3Xf& from, const Eigen::Matrix3Xf& to,
                                           const Eigen::Vector3d& guess) {
  if (from.cols() == 0 || to.cols() == 0) return std::nullopt;
  const Eigen::Index stride = (from.cols() + kMaxFromPoints - 1) / kMaxFromPoints;
  const Eigen::Matrix3Xf sample = from(Eigen::all, Eigen::seq(0, from.cols() - 1, stride));
  const PointIndex index(to);
  const auto normals = normals_of(to, index);
  const ObjectShift a = icp_from(sample, to, index, normals, Eigen::Vector3d(guess.x(), guess.y(), 0.0));
  ObjectShift b = icp_from(sample, to, index, normals, Eigen::Vector3d::Zero());
  ObjectShift best = b.residual < a.residual ? b : a;
  best.ambiguous = (a.translation - b.translation).norm() > kAgree && std::abs(a.residual - b.residual) < kSameFit;
  return best;
}

std::vector<std::vector<double>> object_speeds(const std::vector<std::vector<LabelBox>>& boxes,
                                               const std::vector<std::vector<Eigen::Matrix3Xf>>& points,
                                               const std::vector<Eigen::Isometry3d>& poses,
                                               const std::vector<double>& times, double window,
                                               const ObjectMotionConfig& config) {
  // Each track's links: from one sighting to the next, registered on their points.
  struct Link {
    std::size_t from_scan, from_box, to_scan, to_box;
    std::optional<Eigen::Vector3d> shift;
  };
  std::map<std::string, std::map<std::size_t, std::size_t>> track;  // id -> scan -> box index
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t k = 0; k < boxes[i].size(); ++k) track[boxes[i][k].id][i] = k;
  }
  std::vector<Link> links;
  std::map<std::pair<std::string, std::size_t>, std::size_t> link_from;  // (id, scan) -> its link
  for (const auto& [id, t] : track) {
    for (auto it = t.begin(); std::next(it) != t.end(); ++it) {
      link_from[{id, it->first}] = links.size();
      links.push_back({it->first, it->second, std::next(it)->first, std::next(it)->second, std::nullopt});
    }
  }
  tbb::parallel_for(std::size_t{0}, links.size(), [&](std::size_t j) {
    Link& l = links[j];
    const auto& pa = points.at(l.from_scan).at(l.from_box);
    const auto& pb = points.at(l.to_scan).at(l.to_box);
    if (static_cast<std::size_t>(pa.cols()) < config.min_points ||
        static_cast<std::size_t>(pb.cols()) < config.min_points) {
      return;
    }
    const Eigen::Vector3d guess = poses.at(l.to_scan) * boxes[l.to_scan][l.to_box].centre -
                                  poses.at(l.from_scan) * boxes[l.from_scan][l.from_box].centre;
    const auto shift = register_object(pa, pb, guess);
    if (shift && !shift->ambiguous && shift->residual <= config.max_residual) l.shift = shift->translation;
  });
  const double half = window / 2 + 1e-6;  // stamps are rounded in their files
  std::vector<std::vector<double>> speed(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    speed[i].assign(boxes[i].size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < boxes[i].size(); ++k) {
      const std::string& id = boxes[i][k].id;
      std::size_t a = i, b = i;
      for (const auto& sighting : track.at(id)) {
        if (std::abs(times.at(sighting.first) - times.at(i)) > half) continue;
        a = std::min(a, sighting.first);
        b = std::max(b, sighting.first);
      }
      const double dt = times.at(b) - times.at(a);
      if (a == b || !(dt > 0)) continue;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      bool whole = true;
      for (std::size_t scan = a; whole && scan != b;) {
        const Link& l = links[link_from.at({id, scan})];
        whole = l.shift.has_value();
        if (whole) sum += *l.shift;
        scan = l.to_scan;
      }
      if (whole) speed[i][k] = sum.norm() / dt;
    }
  }
  return speed;
}

namespace {

// Each stale copy (stale_copies) takes the moving flag of its object's nearest sighting in
// time (the earlier on a tie). There is always one: an object's first box is no copy.
std::vector<std::vector<bool>> with_stale_copies(const std::vector<std::vector<LabelBox>>& boxes,
                                                 const std::vector<std::vector<bool>>& stale,
                                                 const std::vector<std::vector<bool>>& sighting_moving) {
  std::map<std::string, std::vector<std::pair<std::size_t, bool>>> sightings;  // id -> (scan, moving)
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t k = 0, s = 0; k < boxes[i].size(); ++k) {
      if (!stale[i][k]) sightings[boxes[i][k].id].emplace_back(i, sighting_moving[i][s++]);
    }
  }
  std::vector<std::vector<bool>> moving(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t k = 0, s = 0; k < boxes[i].size(); ++k) {
      if (!stale[i][k]) {
        moving[i].push_back(sighting_moving[i][s++]);
        continue;
      }
      const auto gap = [i](std::size_t j) { return j > i ? j - i : i - j; };
      const auto& object = sightings.at(boxes[i][k].id);
      const auto* best = &object.front();
      for (const auto& sighting : object) {
        if (gap(sighting.first) < gap(best->first)) best = &sighting;
      }
      moving[i].push_back(best->second);
    }
  }
  return moving;
}

}  // namespace

BoxTruth box_truth(const Sequence& sequence, const std::filesystem::path& boxes_dir,
                   const BoxTruthOptions& options) {
  BoxTruth truth;
  truth.boxes = read_sequence_boxes(boxes_dir, sequence.scans);
  // Motion is measured on the sightings alone: stale copies left out.
  const auto stale = stale_copies(truth.boxes);
  std::vector<std::vector<LabelBox>> sightings(truth.boxes.size());
  for (std::size_t i = 0; i < truth.boxes.size(); ++i) {
    for (std::size_t k = 0; k < truth.boxes[i].size(); ++k) {
      if (stale[i][k]) {
        ++truth.stale_copies;
      } else {
        sightings[i].push_back(truth.boxes[i][k]);
      }
    }
  }
  std::vector<std::vector<double>> speeds;
  if (options.source == BoxSpeedSource::kPoints) {
    std::vector<std::vector<Eigen::Matrix3Xf>> points(sequence.size());
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      if (sightings[i].empty()) continue;
      Scan scan = read_raw_scan(sequence, i);
      drop_invalid(scan);
      const Eigen::Matrix3Xf world =
          options.time_from_azimuth && !scan.has_time()
              ? place_by_azimuth(scan.points, sequence.poses, sequence.times, i, options.pose_reference)
              : to_world(scan, sweep_motion(sequence.poses, sequence.times, i)).points;
      points[i] = points_in_boxes(scan.points, world, sightings[i], options.margin);
    }
    speeds = object_speeds(sightings, points, sequence.poses, sequence.times, options.window);
    for (const auto& s : speeds) {
      for (const double v : s) truth.measured += std::isfinite(v);
    }
  }
  const auto moving_sightings = moving_boxes(sightings, sequence.poses, sequence.times, options.speed,
                                             options.window, speeds.empty() ? nullptr : &speeds);
  truth.moving = with_stale_copies(truth.boxes, stale, moving_sightings);
  if (options.whole_track) truth.moving = moving_tracks(truth.boxes, truth.moving);
  return truth;
}

}  // namespace cleanmap
