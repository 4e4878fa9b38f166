#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/sequence.hpp"

namespace cleanmap {

// A depth-image sequence in the TUM RGB-D layout (the Bonn RGB-D Dynamic dataset uses it too):
//   depth/*.png     16-bit depth images
//   depth.txt       "stamp depth/NAME.png" per frame ('#' lines are comments)
//   groundtruth.txt optional: TUM poses (stamp tx ty tz qx qy qz qw) of the camera's optical
//                   frame, interpolated at the frame stamps (--poses gives another, e.g. a robot
//                   arm's kinematics, as a TUM file or one KITTI pose per frame)
//   camera.yaml     intrinsics (io/depth_image.hpp; --camera gives another file)
//   labels/*.label  optional per-pixel labels (251 moving), for scoring
// Scans are the frames back-projected, one point per pixel (io/depth_image.hpp).
bool is_tum_rgbd(const std::filesystem::path& folder);
Sequence open_tum_rgbd(const std::filesystem::path& folder, const SequenceOptions& options);

// One "stamp file" line per frame.
struct DepthFrameEntry {
  double stamp;
  std::string file;  // relative to the sequence folder
};
std::vector<DepthFrameEntry> read_depth_list(const std::filesystem::path& file);
void write_depth_list(const std::filesystem::path& file, const std::vector<DepthFrameEntry>& frames);

}  // namespace cleanmap
