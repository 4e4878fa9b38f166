#include "mapping/carve_ray.hpp"

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <random>
#include <set>

#include "mapping/cell_set.hpp"

namespace cleanmap {
namespace {

using Key = CellSet::Key;

std::uint64_t morton_of(const Key& k) {
  std::uint64_t m = 0;
  for (int b = 0; b < 16; ++b) {
    for (int a = 0; a < 3; ++a) m |= static_cast<std::uint64_t>((k[a] >> b) & 1u) << (3 * b + a);
  }
  return m;
}

TEST(CellSet, InsertsOnceAndGivesCellsBackInOctreeOrder) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> near(32768 - 80, 32768 + 80);
  CellSet set;
  std::set<Key> truth;
  for (int i = 0; i < 20000; ++i) {
    const Key k{static_cast<std::uint16_t>(near(rng)), static_cast<std::uint16_t>(near(rng)),
                static_cast<std::uint16_t>(near(rng))};
    EXPECT_EQ(set.insert(k), truth.insert(k).second);
  }
  EXPECT_EQ(set.size(), truth.size());
  for (const auto& k : truth) EXPECT_TRUE(set.contains(k));
  EXPECT_FALSE(set.contains(Key{1, 2, 3}));
  EXPECT_FALSE(set.contains(Key{32768 + 81, 32768, 32768}));
  std::vector<Key> out;
  set.for_each_in_tree_order([&](const Key& k) { out.push_back(k); });
  ASSERT_EQ(out.size(), truth.size());
  // Octree order: OctoMap's child index has x in bit 0, then y, then z, at every depth.
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_LT(morton_of(out[i - 1]), morton_of(out[i]));
  EXPECT_EQ(std::set<Key>(out.begin(), out.end()), truth);
}

TEST(CarveRay, IntoAnEmptySetEqualsOctoMapsRayKeys) {
  octomap::OcTree tree(0.3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-40.0, 40.0);
  for (int r = 0; r < 2000; ++r) {
    const Eigen::Vector3d origin(coord(rng) / 10, coord(rng) / 10, coord(rng) / 20);
    Eigen::Vector3d end(coord(rng), coord(rng), coord(rng) / 4);
    if (r % 10 == 0) end.y() = origin.y();  // axis-parallel in y
    octomap::KeyRay ray;
    ASSERT_TRUE(tree.computeRayKeys(octomap::point3d(origin.x(), origin.y(), origin.z()),
                                    octomap::point3d(end.x(), end.y(), end.z()), ray));
    std::set<Key> expected;
    for (const auto& k : ray) expected.insert({k[0], k[1], k[2]});
    // computeRayKeys leaves out the end cell (the hit); carving from the far end includes the
    // origin's cell, which computeRayKeys also holds unless origin and end share a cell.
    const auto o = tree.coordToKey(origin.x(), origin.y(), origin.z());
    const auto e = tree.coordToKey(end.x(), end.y(), end.z());
    if (o != e) expected.insert({o[0], o[1], o[2]});
    CellSet carved;
    carve_ray(tree, end, origin, false, carved);
    std::vector<Key> got;
    carved.for_each_in_tree_order([&](const Key& k) { got.push_back(k); });
    std::size_t differ = 0;
    for (const auto& k : got) differ += !expected.count(k);
    for (const auto& k : expected) differ += !carved.contains(k);
    EXPECT_EQ(differ, 0u) << "ray " << r;
    EXPECT_FALSE(carved.contains({e[0], e[1], e[2]}));
    EXPECT_TRUE(carved.contains({o[0], o[1], o[2]}) || o == e);
  }
}

TEST(CarveRay, StopsAtCellsAnEarlierRayCarved) {
  octomap::OcTree tree(0.5);
  const Eigen::Vector3d origin(0.1, 0.1, 0.1);
  CellSet carved;
  carve_ray(tree, Eigen::Vector3d(20.1, 0.1, 0.1), origin, true, carved);
  EXPECT_EQ(carved.size(), 41u);  // cells 0 .. 40 along x
  // A second ray along the same line from further away adds only its own new cells.
  carve_ray(tree, Eigen::Vector3d(25.1, 0.1, 0.1), origin, true, carved);
  EXPECT_EQ(carved.size(), 51u);
}

}  // namespace
}  // namespace cleanmap
