#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/scan.hpp"

namespace cleanmap {

// A hand-annotated 3D box in the sensor frame (SUSTechPOINTS-style JSON, as in
// shared/data/pandar64_street/boxes): stable object id, type, centre, yaw, full size.
struct LabelBox {
  std::string id;
  std::string type;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // length, width, height
};

// A box grown by `margin` metres on every side, with the frame to test points in: `local(p)`
// is a sensor-frame point in the box's frame (centred, yaw undone), `contains` tests that.
struct GrownBox {
  GrownBox(const LabelBox& box, double margin)
      : to_box(Eigen::AngleAxisd(-box.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix()),
        centre(box.centre),
        half(box.size / 2 + Eigen::Vector3d::Constant(margin)) {}
  Eigen::Vector3d local(const Eigen::Vector3f& p) const { return to_box * (p.cast<double>() - centre); }
  bool contains(const Eigen::Vector3d& q) const { return (q.cwiseAbs().array() <= half.array()).all(); }
  Eigen::Matrix3d to_box;
  Eigen::Vector3d centre, half;
};

std::vector<LabelBox> read_boxes(const std::filesystem::path& file);

// The boxes of each scan of a sequence: `boxes_dir`/<scan file stem>.json, none where that file
// is missing (a scan nobody annotated has no box).
std::vector<std::vector<LabelBox>> read_sequence_boxes(const std::filesystem::path& boxes_dir,
                                                       const std::vector<std::filesystem::path>& scans);

// Per scan and box: is the object moving? Its centre is taken to the world frame with the
// scan's pose; its velocity is the least-squares line through the same id's centres within
// `window` seconds around the scan (window/2 either side); moving when faster than
// `speed_threshold` m/s. Hand-drawn boxes jitter by 0.2-0.5 m from scan to scan: on the
// Pandar64 street a parked truck and people standing at a crossing (net track speed
// 0.02-0.1 m/s) came out at 2-5 m/s from neighbouring scans, moving in most scans. The line
// over 1 s (11 scans at 10 Hz) takes 0.2 m of jitter down to about 0.2 m/s, under the
// threshold. window 0: central differences between the neighbouring sightings, as before.
// `measured[i][k]`, where given and finite, is box k of scan i's speed measured otherwise (on
// the object's own points: object_motion.hpp) and takes the place of the centres' speed.
std::vector<std::vector<bool>> moving_boxes(const std::vector<std::vector<LabelBox>>& boxes,
                                            const std::vector<Eigen::Isometry3d>& poses,
                                            const std::vector<double>& times,
                                            double speed_threshold, double window = 1.0,
                                            const std::vector<std::vector<double>>* measured = nullptr);

// Per scan and box: a stale copy, the very box (centre, yaw and size to the bit) of its object
// in an earlier scan that a scan in between had already replaced. An annotation tool's copy of
// an older frame, not a sighting: on the Pandar64 street, scans 3 and 4 hold 55 and 57
// motorcycle boxes copied from scan 0 in the sensor frame while the car drove 2 m. In scans
// 0-2 those boxes stand still in the world frame (a row of parked scooters), and the copies,
// carried 2 m along with the car, would make them move at 20 m/s. A box copied from the
// frame just before (a car ahead at the sensor's speed, an object the annotator checked) has
// no replacement in between and stays a sighting.
std::vector<std::vector<bool>> stale_copies(const std::vector<std::vector<LabelBox>>& boxes);

// Every box of an object that moves in any scan (`moving`, per scan and box) marked moving in
// every scan: the object's whole track, once it moved at all.
std::vector<std::vector<bool>> moving_tracks(const std::vector<std::vector<LabelBox>>& boxes,
                                             const std::vector<std::vector<bool>>& moving);

// MOS labels for a sensor-frame scan: 251 for points inside a moving box (grown by `margin`
// metres on every side), 9 otherwise.
std::vector<std::uint32_t> labels_from_boxes(const Scan& scan, const std::vector<LabelBox>& boxes,
                                             const std::vector<bool>& moving, double margin = 0.1);

}  // namespace cleanmap
