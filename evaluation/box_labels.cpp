#include "evaluation/box_labels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <nlohmann/json.hpp>

#include "io/error.hpp"
#include "io/label_file.hpp"

namespace cleanmap {

std::vector<LabelBox> read_boxes(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open box file");
  std::vector<LabelBox> boxes;
  try {
    const auto j = nlohmann::json::parse(in);
    for (const auto& b : j) {
      LabelBox box;
      box.id = b.at("obj_id").is_string() ? b.at("obj_id").get<std::string>() : b.at("obj_id").dump();
      box.type = b.value("obj_type", "");
      const auto& psr = b.at("psr");
      box.centre = {psr.at("position").at("x").get<double>(), psr.at("position").at("y").get<double>(),
                    psr.at("position").at("z").get<double>()};
      box.yaw = psr.at("rotation").at("z").get<double>();
      box.size = {psr.at("scale").at("x").get<double>(), psr.at("scale").at("y").get<double>(),
                  psr.at("scale").at("z").get<double>()};
      boxes.push_back(box);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(file, std::string("invalid box JSON: ") + e.what());
  }
  return boxes;
}

std::vector<std::vector<LabelBox>> read_sequence_boxes(const std::filesystem::path& boxes_dir,
                                                       const std::vector<std::filesystem::path>& scans) {
  std::vector<std::vector<LabelBox>> boxes;
  boxes.reserve(scans.size());
  for (const auto& scan : scans) {
    const auto file = boxes_dir / (scan.stem().string() + ".json");
    boxes.push_back(std::filesystem::exists(file) ? read_boxes(file) : std::vector<LabelBox>{});
  }
  return boxes;
}

namespace {

using Track = std::map<std::size_t, Eigen::Vector3d>;  // scan -> world-frame centre

// Speed between the sightings before and after scan i (one-sided at the track's ends).
double central_speed(const Track& t, std::size_t i, const std::vector<double>& times) {
  const auto it = t.find(i);
  const auto before = it == t.begin() ? it : std::prev(it);
  const auto after = std::next(it) == t.end() ? it : std::next(it);
  const double dt = times.at(after->first) - times.at(before->first);
  return dt > 0 ? (after->second - before->second).norm() / dt : 0.0;
}

// Slope of the least-squares line through the sightings within half_window of scan i.
double fitted_speed(const Track& t, std::size_t i, const std::vector<double>& times, double half_window) {
  const double t0 = times.at(i);
  double n = 0, st = 0, stt = 0;
  Eigen::Vector3d sp = Eigen::Vector3d::Zero(), stp = Eigen::Vector3d::Zero();
  for (const auto& [scan, c] : t) {
    const double dt = times.at(scan) - t0;
    if (std::abs(dt) > half_window + 1e-6) continue;  // stamps rounded in their files
    n += 1;
    st += dt;
    stt += dt * dt;
    sp += c;
    stp += dt * c;
  }
  const double var = stt - st * st / n;
  if (n < 3 || var <= 0) return central_speed(t, i, times);  // too few sightings to fit
  return ((stp - st * sp / n) / var).norm();
}

}  // namespace

std::vector<std::vector<bool>> moving_boxes(const std::vector<std::vector<LabelBox>>& boxes,
                                            const std::vector<Eigen::Isometry3d>& poses,
                                            const std::vector<double>& times,
                                            double speed_threshold, double window,
                                            const std::vector<std::vector<double>>* measured) {
  if (!std::isfinite(speed_threshold) || speed_threshold < 0) throw Error("box speed threshold must be a finite number >= 0");
  if (!std::isfinite(window) || window < 0) throw Error("box speed window must be a finite number >= 0 (s)");
  std::map<std::string, Track> track;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (const auto& b : boxes[i]) track[b.id][i] = poses.at(i) * b.centre;
  }
  std::vector<std::vector<bool>> moving(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t k = 0; k < boxes[i].size(); ++k) {
      const double known = measured ? measured->at(i).at(k) : NAN;
      if (std::isfinite(known)) {
        moving[i].push_back(known > speed_threshold);
        continue;
      }
      const Track& t = track[boxes[i][k].id];
      const double speed = window > 0 ? fitted_speed(t, i, times, window / 2) : central_speed(t, i, times);
      moving[i].push_back(speed > speed_threshold);
    }
  }
  return moving;
}

std::vector<std::vector<bool>> stale_copies(const std::vector<std::vector<LabelBox>>& boxes) {
  // A box equals an older one of its object, and a box in between was not that box: it is a
  // copy exactly when its first occurrence lies before the object's trailing run of equal
  // boxes, or the last box differs from it. One look-up per box (the definition, checked
  // against every earlier pair, was cubic in a track's length). Compared with ==, as copied
  // boxes agree to the bit; a NaN matches nothing.
  using Key = std::array<double, 7>;
  struct Trail {
    std::map<Key, std::size_t> first;  // box -> index of its first occurrence
    Key last{};
    std::size_t count = 0, run_start = 0;  // the trailing run of equal boxes starts at run_start
  };
  std::map<std::string, Trail> trails;
  std::vector<std::vector<bool>> stale(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (const auto& b : boxes[i]) {
      const Key key{b.centre.x(), b.centre.y(), b.centre.z(), b.yaw, b.size.x(), b.size.y(), b.size.z()};
      const bool finite = std::all_of(key.begin(), key.end(), [](double v) { return !std::isnan(v); });
      auto& t = trails[b.id];
      const auto e = finite ? t.first.find(key) : t.first.end();
      const bool same_as_last = t.count > 0 && t.last == key;
      stale[i].push_back(e != t.first.end() && (!same_as_last || e->second < t.run_start));
      if (!same_as_last) t.run_start = t.count;
      if (finite) t.first.emplace(key, t.count);
      t.last = key;
      ++t.count;
    }
  }
  return stale;
}

std::vector<std::vector<bool>> moving_tracks(const std::vector<std::vector<LabelBox>>& boxes,
                                             const std::vector<std::vector<bool>>& moving) {
  std::set<std::string> movers;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t k = 0; k < boxes[i].size(); ++k) {
      if (moving.at(i).at(k)) movers.insert(boxes[i][k].id);
    }
  }
  std::vector<std::vector<bool>> out(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (const auto& b : boxes[i]) out[i].push_back(movers.count(b.id) > 0);
  }
  return out;
}

std::vector<std::uint32_t> labels_from_boxes(const Scan& scan, const std::vector<LabelBox>& boxes,
                                             const std::vector<bool>& moving, double margin) {
  std::vector<std::uint32_t> labels(scan.size(), kLabelStatic);
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    if (!moving[k]) continue;
    const GrownBox box(boxes[k], margin);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (box.contains(box.local(scan.points.col(static_cast<Eigen::Index>(i))))) labels[i] = kLabelMoving;
    }
  }
  return labels;
}

}  // namespace cleanmap
