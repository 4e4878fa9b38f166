#include "io/pose_file.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "io/close_checked.hpp"
#include "io/error.hpp"

namespace cleanmap {

Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double s) {
  const Eigen::AngleAxisd delta(a.linear().transpose() * b.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = a.linear() * Eigen::AngleAxisd(s * delta.angle(), delta.axis()).toRotationMatrix();
  out.translation() = a.translation() + s * (b.translation() - a.translation());
  return out;
}

namespace {

// Splits a line into finite numbers; fails naming the line otherwise.
std::vector<double> numbers(const std::string& line, const std::filesystem::path& file, int row) {
  std::istringstream in(line);
  std::vector<double> out;
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) {
      fail(file, "line " + std::to_string(row) + ": '" + token + "' is not a finite number");
    }
    out.push_back(v);
  }
  return out;
}

std::ifstream open(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) fail(file, "no such file");
  std::ifstream in(file);
  if (!in) fail(file, "cannot open file");
  return in;
}

bool blank_or_comment(const std::string& line) {
  const auto p = line.find_first_not_of(" \t\r");
  return p == std::string::npos || line[p] == '#';
}

Eigen::Isometry3d from_3x4(const std::vector<double>& v, std::size_t first = 0) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = v[first + 4 * r + c];
  }
  // Files store rotations to ~7 digits; re-orthonormalise so compositions stay rigid.
  const Eigen::Quaterniond q(pose.linear());
  pose.linear() = q.normalized().toRotationMatrix();
  return pose;
}

std::ofstream create(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) fail(file, "cannot create file");
  out << std::setprecision(9);
  return out;
}

}  // namespace

PoseFormat parse_pose_format(const std::string& text) {
  if (text == "auto") return PoseFormat::kAuto;
  if (text == "kitti") return PoseFormat::kKitti;
  if (text == "tum") return PoseFormat::kTum;
  throw Error("unknown pose format '" + text + "' (expected auto, kitti or tum)");
}

std::vector<StampedPose> read_poses(const std::filesystem::path& file, PoseFormat format) {
  auto in = open(file);
  std::vector<StampedPose> poses;
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (blank_or_comment(line)) continue;
    const auto v = numbers(line, file, row);
    if (format == PoseFormat::kAuto) {
      if (v.size() == 12) format = PoseFormat::kKitti;
      else if (v.size() == 8) format = PoseFormat::kTum;
      else fail(file, "line " + std::to_string(row) + " has " + std::to_string(v.size()) +
                          " columns; expected 12 (KITTI 3x4) or 8 (TUM t x y z qx qy qz qw)");
    }
    const std::size_t want = format == PoseFormat::kKitti ? 12 : 8;
    if (v.size() != want) {
      fail(file, "line " + std::to_string(row) + " has " + std::to_string(v.size()) +
                     " columns; expected " + std::to_string(want));
    }
    StampedPose p;
    if (format == PoseFormat::kKitti) {
      p.stamp = std::nan("");
      p.pose = from_3x4(v);
    } else {
      p.stamp = v[0];
      const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
      if (q.norm() < 1e-6) fail(file, "line " + std::to_string(row) + ": zero quaternion");
      p.pose.linear() = q.normalized().toRotationMatrix();
      p.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    }
    poses.push_back(p);
  }
  if (poses.empty()) fail(file, "contains no poses");
  return poses;
}

void write_kitti_poses(const std::filesystem::path& file,
                       const std::vector<Eigen::Isometry3d>& poses) {
  auto out = create(file);
  for (const auto& p : poses) {
    const auto& m = p.matrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) out << m(r, c) << ((r == 2 && c == 3) ? '\n' : ' ');
    }
  }
  close_checked(out, file);
}

void write_tum_poses(const std::filesystem::path& file, const std::vector<StampedPose>& poses) {
  auto out = create(file);
  for (const auto& p : poses) {
    const Eigen::Quaterniond q(p.pose.rotation());
    const auto& t = p.pose.translation();
    out << std::fixed << std::setprecision(6) << p.stamp << std::defaultfloat
        << std::setprecision(9) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x()
        << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  close_checked(out, file);
}

std::vector<double> read_times(const std::filesystem::path& file) {
  auto in = open(file);
  std::vector<double> times;
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (blank_or_comment(line)) continue;
    const auto v = numbers(line, file, row);
    if (v.size() != 1) {
      fail(file, "line " + std::to_string(row) + " has " + std::to_string(v.size()) +
                     " columns; expected one time in seconds");
    }
    times.push_back(v[0]);
  }
  if (times.empty()) fail(file, "contains no times");
  return times;
}

Eigen::Isometry3d read_kitti_calib_tr(const std::filesystem::path& file) {
  auto in = open(file);
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.rfind("Tr:", 0) != 0) continue;
    const auto v = numbers(line.substr(3), file, row);
    if (v.size() != 12) fail(file, "Tr has " + std::to_string(v.size()) + " values; expected 12");
    return from_3x4(v);
  }
  fail(file, "has no 'Tr:' line");
}

}  // namespace cleanmap
