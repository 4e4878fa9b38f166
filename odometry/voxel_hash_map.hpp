#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <vector>

#include "geometry/voxel_key.hpp"

namespace cleanmap {

// The local map: world points in a voxel hash, at most `max_points` per voxel, voxels beyond
// `max_distance` of the sensor dropped (KISS-ICP's VoxelHashMap).
struct VoxelHashMap {
  double voxel_size = 1.0;
  double max_distance = 100.0;
  int max_points = 20;
  tsl::robin_map<VoxelKey, std::vector<Eigen::Vector3d>, VoxelKeyHash> voxels;

  bool empty() const { return voxels.empty(); }
  std::size_t point_count() const;

  // A point closer than min_spacing() to one the voxel holds is not added: a still sensor
  // would otherwise fill each voxel with copies of the same few samples, and the k nearest
  // neighbours of a point would span one sample's range noise instead of the surface (the
  // planes then turn random, and registration from rest stuck at zero motion). The spacing
  // lets max_points samples cover a voxel's face evenly (as KISS-ICP 1.x does).
  void add(const std::vector<Eigen::Vector3d>& points);
  double min_spacing() const;
  void remove_far(const Eigen::Vector3d& origin);
  // Removes map points within `radius` of any of the given points (dynamic-point feedback).
  std::size_t remove_near(const std::vector<Eigen::Vector3d>& points, double radius);

  // Up to k map points closest to q among the 27 voxels around it, within max_dist.
  void nearest(const Eigen::Vector3d& q, int k, double max_dist,
               std::vector<Eigen::Vector3d>& out) const;
};

}  // namespace cleanmap
