#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "mapping/cell_set.hpp"
#include "mapping/sweep_origin.hpp"

namespace octomap {
class OcTree;
}

namespace cleanmap {

struct MapConfig {
  double resolution = 0.3;       // m, leaf size
  double max_range = 30.0;       // m: longer rays are cut (and end without an occupied cell)
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  double insert_voxel = 0.6;     // m: subsample that casts the rays (every point marks its cell)
  // Free-space second opinion: a point that falls in a cell seen free at least this confidently
  // (occupancy probability at most this) is evidence of motion.
  double free_probability = 0.2;
};

void validate(const MapConfig& config);

// The clean map: an OctoMap of static points only, free space carved by casting rays from
// where the sensor was.
class OctoMapBuilder {
 public:
  explicit OctoMapBuilder(const MapConfig& config);
  ~OctoMapBuilder();

  // World-frame points of one scan and its sensor origin; insert only the static ones.
  void insert(const Eigen::Matrix3Xf& points, const Eigen::Vector3d& origin);
  // The same, each ray cast from where the sensor was at its point's time (`times` relative to
  // the scan's stamp, as Scan::time; one per point, or empty: all from sensor.at(0)). The
  // VisibilityMap's rays start so too (SweepOrigin says why); these carve 0.3 m cells from a
  // 0.6 m subsample, so one origin per ray is exact and costs nothing.
  void insert(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times,
              const SweepOrigin& sensor);

  // Per point: 1 when its cell was confidently observed free so far (a hit in free space).
  std::vector<std::uint8_t> hits_in_free_space(const Eigen::Matrix3Xf& points) const;

  void write_binary(const std::filesystem::path& file);  // .bt: maximum-likelihood occupancy
  void write_full(const std::filesystem::path& file);    // .ot: full probabilities
  // 2D occupancy grid between two heights in the ROS map_server format (PGM + YAML).
  void write_occupancy_grid(const std::filesystem::path& pgm, double z_min, double z_max);

  // Cells to be occupied at the end whatever rays do to them later (`points`, world frame,
  // within max_range of where the sensor was at each point's time, exactly as insert): static
  // points the whole log saw standing at least as often as gone through (seen_standing, pass 2).
  // occupy_pinned raises each to at least one hit's log-odds (prob_hit), and returns how many it
  // raised.
  void pin(const Eigen::Matrix3Xf& points, const Eigen::VectorXf& times, const SweepOrigin& sensor);
  std::size_t occupy_pinned();

  std::size_t leaf_count() const;
  // Points inserted so far that lay beyond the tree's 16-bit keys (32768 cells from its origin
  // along each axis: 9.8 km at 0.3 m), left out of the map.
  std::size_t points_beyond_reach() const { return beyond_reach_; }
  // How far the tree reaches from its origin along each axis, m.
  double reach() const { return config_.resolution * 32768.0; }
  const octomap::OcTree& tree() const { return *tree_; }

 private:
  MapConfig config_;
  std::unique_ptr<octomap::OcTree> tree_;
  std::unique_ptr<CellSet> pinned_;
  std::size_t beyond_reach_ = 0;
};

}  // namespace cleanmap
