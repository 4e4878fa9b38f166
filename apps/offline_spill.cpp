#include "apps/offline_spill.hpp"

#include <cstring>
#include <fstream>
#include <string>

#include "io/error.hpp"

namespace cleanmap::app {
namespace {

constexpr char kMagic[8] = {'C', 'M', 'S', 'P', 'I', 'L', 'L', '2'};  // 2: per-point times

template <typename T>
void put(std::ofstream& f, const T& v) {
  f.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <typename T>
void put_array(std::ofstream& f, const T* data, std::size_t n) {
  put(f, static_cast<std::uint64_t>(n));
  f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n * sizeof(T)));
}

struct Reader {
  std::ifstream f;
  std::filesystem::path file;
  std::uint64_t left = 0;  // bytes not read yet: no array may claim more
  template <typename T>
  T get() {
    T v{};
    if (left < sizeof v || !f.read(reinterpret_cast<char*>(&v), sizeof v)) fail(file, "truncated spill file");
    left -= sizeof v;
    return v;
  }
  template <typename T>
  void get_array(T* data, std::size_t n) {
    if (left < n * sizeof(T) || !f.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(n * sizeof(T)))) {
      fail(file, "truncated spill file");
    }
    left -= n * sizeof(T);
  }
  std::size_t count(std::size_t element) {
    const auto n = get<std::uint64_t>();
    if (n > left / element) fail(file, "spill file claims more data than it holds");
    return static_cast<std::size_t>(n);
  }
};

}  // namespace

void write_spill(const std::filesystem::path& file, const ScoredScan& r, const std::vector<std::uint32_t>& labels) {
  std::ofstream f(file, std::ios::binary | std::ios::trunc);
  if (!f) fail(file, "cannot write");
  const Scan& s = r.scan;
  f.write(kMagic, sizeof kMagic);
  put(f, static_cast<std::uint64_t>(r.index));
  put(f, s.stamp);
  const Eigen::Matrix4d pose = s.pose ? s.pose->matrix() : Eigen::Matrix4d::Identity();
  put(f, static_cast<std::uint8_t>(s.pose.has_value()));
  f.write(reinterpret_cast<const char*>(pose.data()), sizeof(double) * 16);
  put_array(f, s.name.data(), s.name.size());
  put(f, static_cast<std::uint64_t>(s.input_size));
  put_array(f, s.points.data(), static_cast<std::size_t>(s.points.size()));
  put_array(f, s.intensity.data(), static_cast<std::size_t>(s.intensity.size()));
  put_array(f, s.time.data(), static_cast<std::size_t>(s.time.size()));
  put_array(f, s.input_index.data(), s.input_index.size());
  put_array(f, r.score.data(), r.score.size());
  put_array(f, r.dynamic.data(), r.dynamic.size());
  put_array(f, labels.data(), labels.size());
  for (const auto v : {r.downsampled, r.scored_downsampled, r.dynamic_before_completion, r.dynamic_downsampled,
                       r.tracked_points}) {
    put(f, static_cast<std::uint64_t>(v));
  }
  put(f, static_cast<std::int32_t>(r.scans_before));
  put(f, static_cast<std::int32_t>(r.scans_after));
  put(f, r.voxel_size);
  put(f, r.seconds);
  if (!f) fail(file, "write failed (disk full?)");
}

SpilledScan read_spill(const std::filesystem::path& file) {
  Reader in{std::ifstream(file, std::ios::binary), file};
  if (!in.f) fail(file, "cannot read spill file");
  in.left = std::filesystem::file_size(file);
  char magic[8];
  in.get_array(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) fail(file, "not a cleanmap spill file");
  SpilledScan out;
  ScoredScan& r = out.scored;
  Scan& s = r.scan;
  r.index = static_cast<std::size_t>(in.get<std::uint64_t>());
  s.stamp = in.get<double>();
  const bool has_pose = in.get<std::uint8_t>() != 0;
  Eigen::Matrix4d pose;
  in.get_array(pose.data(), 16);
  if (has_pose) s.pose = Eigen::Isometry3d(pose);
  s.name.resize(in.count(1));
  in.get_array(s.name.data(), s.name.size());
  s.input_size = static_cast<std::size_t>(in.get<std::uint64_t>());
  const auto n3 = in.count(sizeof(float));
  if (n3 % 3 != 0) fail(file, "point array is not x y z triples");
  s.points.resize(3, static_cast<Eigen::Index>(n3 / 3));
  in.get_array(s.points.data(), n3);
  const std::size_t n = n3 / 3;
  auto sized = [&](std::size_t got, const char* what) {
    if (got != 0 && got != n) fail(file, std::string(what) + ": " + std::to_string(got) + " values for " + std::to_string(n) + " points");
    return got;
  };
  s.intensity.resize(static_cast<Eigen::Index>(sized(in.count(sizeof(float)), "intensity")));
  in.get_array(s.intensity.data(), static_cast<std::size_t>(s.intensity.size()));
  s.time.resize(static_cast<Eigen::Index>(sized(in.count(sizeof(float)), "times")));
  in.get_array(s.time.data(), static_cast<std::size_t>(s.time.size()));
  s.input_index.resize(sized(in.count(sizeof(std::int32_t)), "input index"));
  in.get_array(s.input_index.data(), s.input_index.size());
  r.score.resize(sized(in.count(sizeof(float)), "scores"));
  in.get_array(r.score.data(), r.score.size());
  r.dynamic.resize(sized(in.count(1), "decisions"));
  in.get_array(r.dynamic.data(), r.dynamic.size());
  if (r.score.size() != n || r.dynamic.size() != n) fail(file, "scores or decisions missing");
  out.labels.resize(sized(in.count(sizeof(std::uint32_t)), "labels"));
  in.get_array(out.labels.data(), out.labels.size());
  for (std::size_t* v : {&r.downsampled, &r.scored_downsampled, &r.dynamic_before_completion, &r.dynamic_downsampled,
                         &r.tracked_points}) {
    *v = static_cast<std::size_t>(in.get<std::uint64_t>());
  }
  r.scans_before = in.get<std::int32_t>();
  r.scans_after = in.get<std::int32_t>();
  r.voxel_size = in.get<double>();
  r.seconds = in.get<double>();
  return out;
}

}  // namespace cleanmap::app
