#include "mapping/octomap_builder.hpp"

#include <cstring>
#include <octomap/OcTree.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <set>

#include "io/cloud_file.hpp"
#include "io/error.hpp"
#include "mapping/free_space_vote.hpp"
#include "mapping/point_cloud_map.hpp"
#include "tests/test_support.hpp"

namespace cleanmap {
namespace {

// A wall at x = 10 seen from the origin: a fan of points on it.
Eigen::Matrix3Xf wall(double x) {
  Eigen::Matrix3Xf p(3, 41 * 21);
  int k = 0;
  for (int i = -20; i <= 20; ++i) {
    for (int j = -10; j <= 10; ++j) p.col(k++) = Eigen::Vector3f(static_cast<float>(x), 0.1f * i, 0.1f * j);
  }
  return p;
}

TEST(OctoMapBuilder, CarvesFreeSpaceAndMarksHitsAndWritesReadableMaps) {
  test::TempDir dir;
  OctoMapBuilder map(MapConfig{});
  for (int k = 0; k < 6; ++k) map.insert(wall(10), Eigen::Vector3d::Zero());
  const auto& tree = map.tree();
  const auto* wall_cell = tree.search(10.0, 0.0, 0.0);
  ASSERT_NE(wall_cell, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(wall_cell));
  const auto* between = tree.search(5.0, 0.0, 0.0);
  ASSERT_NE(between, nullptr);
  EXPECT_FALSE(tree.isNodeOccupied(between));
  // Something standing at x = 5 now is in space seen free; the wall itself is not.
  const auto intruder = map.hits_in_free_space(wall(5));
  const auto wall_hits = map.hits_in_free_space(wall(10));
  EXPECT_GT(std::count(intruder.begin(), intruder.end(), 1), 50);  // on the carved rays
  EXPECT_EQ(std::count(wall_hits.begin(), wall_hits.end(), 1), 0);

  map.write_binary(dir / "map.bt");
  map.write_full(dir / "map.ot");
  map.write_occupancy_grid(dir / "grid.pgm", -1.0, 1.0);
  octomap::OcTree loaded(0.1);
  ASSERT_TRUE(loaded.readBinary((dir / "map.bt").string()));
  EXPECT_DOUBLE_EQ(loaded.getResolution(), MapConfig{}.resolution);
  const auto* cell = loaded.search(10.0, 0.0, 0.0);
  ASSERT_NE(cell, nullptr);
  EXPECT_TRUE(loaded.isNodeOccupied(cell));
  std::unique_ptr<octomap::AbstractOcTree> full(octomap::AbstractOcTree::read((dir / "map.ot").string()));
  ASSERT_NE(full, nullptr);
  EXPECT_EQ(full->getTreeType(), "OcTree");
  EXPECT_TRUE(std::filesystem::exists(dir / "grid.yaml"));
}

TEST(OctoMapBuilder, FullMapKeepsProbabilitiesWhenWrittenAfterTheBinaryOne) {
  test::TempDir dir;
  OctoMapBuilder map(MapConfig{});
  map.insert(wall(10), Eigen::Vector3d::Zero());  // one hit: far from the clamping bounds
  map.write_binary(dir / "map.bt");
  map.write_full(dir / "map.ot");
  std::unique_ptr<octomap::AbstractOcTree> full(octomap::AbstractOcTree::read((dir / "map.ot").string()));
  ASSERT_NE(full, nullptr);
  const auto* kept = static_cast<octomap::OcTree*>(full.get())->search(10.0, 0.0, 0.0);
  ASSERT_NE(kept, nullptr);
  EXPECT_FLOAT_EQ(kept->getLogOdds(), octomap::logodds(MapConfig{}.prob_hit));
  EXPECT_FLOAT_EQ(map.tree().search(10.0, 0.0, 0.0)->getLogOdds(), octomap::logodds(MapConfig{}.prob_hit));
}

TEST(OctoMapBuilder, BinaryMapIsWrittenPrunedAsOctoMapWouldPruneIt) {
  // Hits and misses of different counts leave children with different log-odds but the same
  // free / occupied state: the .bt must hold them merged, as OctoMap's read-prune-write does
  // (issue 15: 162,709 B written against 118,161 B after the round trip).
  test::TempDir dir;
  OctoMapBuilder map(MapConfig{});
  for (int k = 0; k < 3; ++k) map.insert(wall(10), Eigen::Vector3d::Zero());
  map.insert(wall(6), Eigen::Vector3d(0, 0.35, 0));
  map.write_binary(dir / "map.bt");
  octomap::OcTree again(0.1);
  ASSERT_TRUE(again.readBinary((dir / "map.bt").string()));
  const std::size_t leaves = again.getNumLeafNodes();
  again.prune();
  EXPECT_EQ(again.getNumLeafNodes(), leaves);
  ASSERT_TRUE(again.writeBinary((dir / "again.bt").string()));
  EXPECT_EQ(std::filesystem::file_size(dir / "map.bt"), std::filesystem::file_size(dir / "again.bt"));
  EXPECT_LT(leaves, map.tree().getNumLeafNodes());  // the probabilistic tree keeps its detail
}

TEST(OctoMapBuilder, GridBandIsMeasuredAboveTheLocalGround) {
  // A car-mounted sensor 2 m above a street that climbs 6% (world z = 0 at the sensor), a
  // 1.5 m box on it at x = 5: with the default band 0.3-2.0 m above the ground the box is an
  // obstacle and the road is not. Measured from the sensor's height the band lay 2.3-4 m above
  // the road (nothing in it), and a flat-world ground would put the far road in the band.
  test::TempDir dir;
  MapConfig config;
  config.resolution = 0.2;
  OctoMapBuilder map(config);
  auto road = [](double x) { return -2.0 + 0.06 * x; };
  std::vector<Eigen::Vector3f> pts;
  for (double x = 1; x <= 25; x += 0.1) {
    for (double y = -3; y <= 3; y += 0.1) pts.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(road(x)));
  }
  for (double y = -0.5; y <= 0.5; y += 0.05) {
    for (double z = road(5) + 0.1; z <= road(5) + 1.5; z += 0.05) {
      pts.emplace_back(5.0f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  // A canopy 2.6 m above the road at x = 12: no obstacle for the grid (its column's own lowest
  // cell is the canopy, the ground is the road beside it).
  for (double x = 11; x <= 13; x += 0.05) {
    for (double y = -1; y <= 1; y += 0.05) {
      pts.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(road(x) + 2.6));
    }
  }
  Eigen::Matrix3Xf cloud(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t k = 0; k < pts.size(); ++k) cloud.col(static_cast<Eigen::Index>(k)) = pts[k];
  map.insert(cloud, Eigen::Vector3d::Zero());
  map.write_occupancy_grid(dir / "grid.pgm", 0.3, 2.0);
  std::ifstream in(dir / "grid.pgm", std::ios::binary);
  std::string magic;
  int w = 0, h = 0, maxval = 0;
  in >> magic >> w >> h >> maxval;
  in.get();
  std::vector<unsigned char> px(static_cast<std::size_t>(w) * h);
  in.read(reinterpret_cast<char*>(px.data()), static_cast<std::streamsize>(px.size()));
  double x0 = 0, y0 = 0;
  std::ifstream meta(dir / "grid.yaml");
  for (std::string line; std::getline(meta, line);) {
    if (line.rfind("origin: [", 0) == 0) std::sscanf(line.c_str(), "origin: [%lf, %lf", &x0, &y0);
  }
  auto at = [&](double x, double y) {
    const int cx = static_cast<int>((x - x0) / 0.2), cy = static_cast<int>((y - y0) / 0.2);
    return px[static_cast<std::size_t>(h - 1 - cy) * w + cx];
  };
  EXPECT_EQ(at(5.05, 0.05), 0);  // the box
  EXPECT_NE(at(12.05, 0.05), 0);  // under the canopy
  std::size_t occupied = 0;
  for (auto v : px) occupied += v == 0;
  EXPECT_LT(occupied, 20u);  // the box's cells, not the road's
}

TEST(OctoMapBuilder, RepeatedUpdatesClampAsOctoMapDoes) {
  const MapConfig config;
  OctoMapBuilder map(config);
  const auto& tree = map.tree();
  for (int k = 0; k < 30; ++k) map.insert(wall(10), Eigen::Vector3d::Zero());
  const auto* hit = tree.search(10.0, 0.0, 0.0);
  const auto* free = tree.search(5.0, 0.0, 0.0);
  ASSERT_NE(hit, nullptr);
  ASSERT_NE(free, nullptr);
  EXPECT_FLOAT_EQ(hit->getLogOdds(), octomap::logodds(config.clamp_max));
  EXPECT_FLOAT_EQ(free->getLogOdds(), octomap::logodds(config.clamp_min));
  // One hit on a fresh map: exactly the hit log-odds, as octomap's updateNode gives.
  OctoMapBuilder once(config);
  once.insert(wall(10), Eigen::Vector3d::Zero());
  EXPECT_FLOAT_EQ(once.tree().search(10.0, 0.0, 0.0)->getLogOdds(), octomap::logodds(config.prob_hit));
  EXPECT_FLOAT_EQ(once.tree().search(5.0, 0.0, 0.0)->getLogOdds(), octomap::logodds(config.prob_miss));
}

TEST(OctoMapBuilder, ARayIsCarvedFromWhereTheSensorWasWhenItFired) {
  // The sensor moves along y at 10 m/s; the point it hit 0.1 s into the sweep, at (10, 1, 0),
  // was fired from (0, 1, 0): its ray runs along x at y = 1, not from the stamp's (0, 0, 0).
  const SweepOrigin sensor{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 10, 0)};
  const Eigen::Matrix3Xf point = Eigen::Vector3f(10, 1, 0);
  const MapConfig config;
  OctoMapBuilder timed(config), untimed(config);
  timed.insert(point, Eigen::VectorXf::Constant(1, 0.1f), sensor);
  untimed.insert(point, Eigen::VectorXf(), sensor);  // no times: every ray from sensor.at(0)
  const auto miss = octomap::logodds(config.prob_miss);
  const auto* on_path = timed.tree().search(5.0, 1.0, 0.0);
  ASSERT_NE(on_path, nullptr);
  EXPECT_FLOAT_EQ(on_path->getLogOdds(), miss);
  EXPECT_EQ(timed.tree().search(5.0, 0.45, 0.0), nullptr);   // the stamp's ray passes here
  EXPECT_EQ(timed.tree().search(0.15, 0.15, 0.0), nullptr);  // the stamp's origin: never carved
  EXPECT_TRUE(timed.tree().isNodeOccupied(timed.tree().search(10.0, 1.0, 0.0)));
  ASSERT_NE(untimed.tree().search(5.0, 0.45, 0.0), nullptr);
  EXPECT_FLOAT_EQ(untimed.tree().search(5.0, 0.45, 0.0)->getLogOdds(), miss);
  EXPECT_EQ(untimed.tree().search(5.0, 1.0, 0.0), nullptr);
}

TEST(OctoMapBuilder, APinnedCellIsOccupiedAtTheEndWhateverRaysDidToIt) {
  const MapConfig config;
  OctoMapBuilder map(config);
  const auto& tree = map.tree();
  map.insert(wall(10), Eigen::Vector3d::Zero());
  map.pin(wall(10), Eigen::VectorXf(), SweepOrigin{});
  map.pin(wall(40), Eigen::VectorXf(),
          SweepOrigin{});  // beyond max_range (30 m): as insert, not a hit
  // A wall at 20 m seen through the first one's place six times: its cells go free.
  for (int k = 0; k < 6; ++k) map.insert(wall(20), Eigen::Vector3d::Zero());
  ASSERT_FALSE(tree.isNodeOccupied(tree.search(10.0, 0.0, 0.0)));
  const auto at_20 = tree.search(20.0, 0.0, 0.0)->getLogOdds();
  map.pin(wall(20), Eigen::VectorXf(), SweepOrigin{});  // more than one hit already: left as it is
  // The cells of the first wall the rays left under one hit's log-odds: those it raises.
  const float hit = octomap::logodds(config.prob_hit);
  std::set<std::array<std::uint16_t, 3>> below;
  const Eigen::Matrix3Xf first = wall(10);
  for (Eigen::Index i = 0; i < first.cols(); ++i) {
    const auto key = tree.coordToKey(first(0, i), first(1, i), first(2, i));
    if (tree.search(key)->getLogOdds() < hit) below.insert({key[0], key[1], key[2]});
  }
  ASSERT_GT(below.size(), 10u);
  EXPECT_EQ(map.occupy_pinned(), below.size());
  for (const auto& k : below)
    EXPECT_FLOAT_EQ(tree.search(octomap::OcTreeKey(k[0], k[1], k[2]))->getLogOdds(), hit);
  EXPECT_FLOAT_EQ(tree.search(20.0, 0.0, 0.0)->getLogOdds(), at_20);
  EXPECT_EQ(tree.search(40.0, 0.0, 0.0), nullptr);
  EXPECT_EQ(map.occupy_pinned(), 0u);  // nothing left to raise
}

TEST(OctoMapBuilder, APointIsPinnedWithinRangeOfWhereTheSensorWasAsItIsInserted) {
  // The sensor moves along x at 10 m/s; the point 30.5 m from the stamp's origin was fired
  // 0.1 s into the sweep, from (1, 0, 0): 29.5 m, within max_range (30 m). Both insert and pin
  // read the range from there, so a cell is never pinned that was not inserted, or the reverse.
  const SweepOrigin sensor{Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 0, 0)};
  const Eigen::Matrix3Xf point = Eigen::Vector3f(30.5f, 0, 0);
  const Eigen::VectorXf late = Eigen::VectorXf::Constant(1, 0.1f);
  const MapConfig config;
  OctoMapBuilder inserted(config), pinned(config), from_stamp(config);
  inserted.insert(point, late, sensor);
  pinned.pin(point, late, sensor);
  from_stamp.pin(point, Eigen::VectorXf(), sensor);  // no times: from sensor.at(0), 30.5 m
  ASSERT_NE(inserted.tree().search(30.5, 0.0, 0.0), nullptr);
  EXPECT_TRUE(inserted.tree().isNodeOccupied(inserted.tree().search(30.5, 0.0, 0.0)));
  EXPECT_EQ(pinned.occupy_pinned(), 1u);
  EXPECT_FLOAT_EQ(pinned.tree().search(30.5, 0.0, 0.0)->getLogOdds(),
                  octomap::logodds(config.prob_hit));
  EXPECT_EQ(from_stamp.occupy_pinned(), 0u);
}

TEST(OctoMapBuilder, AFullDiskFailsEveryMapWriteNamingTheFile) {
  // /dev/full refuses every write, as a full disk does; OctoMap's own file writers return true
  // there (a warning on stderr), and a truncated map.ot was reported complete.
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  test::TempDir dir;
  OctoMapBuilder map(MapConfig{});
  for (int k = 0; k < 3; ++k) map.insert(wall(10), Eigen::Vector3d::Zero());
  for (const char* name : {"map.bt", "map.ot", "grid.pgm"})
    std::filesystem::create_symlink("/dev/full", dir / name);
  test::expect_error([&] { map.write_binary(dir / "map.bt"); }, {"map.bt", "disk full"});
  test::expect_error([&] { map.write_full(dir / "map.ot"); }, {"map.ot", "disk full"});
  test::expect_error([&] { map.write_occupancy_grid(dir / "grid.pgm", 0.3, 2.0); },
                     {"grid.pgm", "disk full"});
  std::filesystem::remove(dir / "grid.pgm");
  std::filesystem::create_symlink("/dev/full", dir / "grid.yaml");
  test::expect_error([&] { map.write_occupancy_grid(dir / "grid.pgm", 0.3, 2.0); },
                     {"grid.yaml", "disk full"});
}

TEST(FreeSpaceVote, ClusterInFreeSpaceIsDynamicAsAWhole) {
  OctoMapBuilder map(MapConfig{});
  for (int k = 0; k < 6; ++k) map.insert(wall(10), Eigen::Vector3d::Zero());
  // A flat object at x = 5, inside the cone of rays the wall carved (half its size at half
  // the distance), and the wall (static) in one scan.
  Eigen::Matrix3Xf object = wall(5);
  object.bottomRows<2>() *= 0.5f;
  Eigen::Matrix3Xf scan(3, 2 * 41 * 21);
  scan << object, wall(10);
  const auto no_ground = [](const Eigen::Matrix3Xf& s) { return std::vector<std::uint8_t>(static_cast<std::size_t>(s.cols()), 0); };
  const auto dyn = free_space_objects(scan, no_ground, [&](const Eigen::Matrix3Xf& s) { return map.hits_in_free_space(s); }, kFreeSpaceRule);
  EXPECT_EQ(std::count(dyn.begin(), dyn.begin() + 41 * 21, 1), 41 * 21);
  EXPECT_EQ(std::count(dyn.begin() + 41 * 21, dyn.end(), 1), 0);
}

TEST(PointCloudMap, KeepsRawPointsOnePerVoxelWithFields) {
  test::TempDir dir;
  Scan s;
  s.points = wall(3);
  s.intensity = Eigen::VectorXf::Constant(s.points.cols(), 7.0f);
  PointCloudMap map(0.25);
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(s.points.cols()), 1);
  std::vector<float> score(keep.size(), 0.5f);
  map.add(s, keep, score, 4);
  EXPECT_LT(map.size(), keep.size());
  map.write(dir / "m.pcd");
  const Scan r = read_cloud(dir / "m.pcd");
  ASSERT_EQ(r.size(), map.size());
  // Every kept point is one of the input points, not a voxel centre.
  for (Eigen::Index i = 0; i < r.points.cols(); ++i) {
    EXPECT_LT(((s.points.colwise() - r.points.col(i)).colwise().norm()).minCoeff(), 1e-6);
  }
}

// The rows of every scan, in order, with their fields; a scan without intensity drops the
// field for the whole cloud; points() and both formats agree.
TEST(PointCloudMap, WritesEveryScansRowsWithTheirFieldsToEachFile) {
  test::TempDir dir;
  PointCloudMap map;
  Scan a;
  a.points = Eigen::Matrix3Xf::Random(3, 5);
  a.intensity = Eigen::VectorXf::LinSpaced(5, 1.0f, 5.0f);
  map.add(a, {1, 0, 1, 1, 0}, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f}, 2);
  map.write(dir / "with.pcd");
  {
    const Scan r = read_cloud(dir / "with.pcd");
    ASSERT_EQ(r.size(), 3u);
    ASSERT_TRUE(r.has_intensity());
    EXPECT_EQ(r.points.col(1), a.points.col(2));
    EXPECT_EQ(r.intensity[2], 4.0f);
  }
  Scan b;
  b.points = Eigen::Matrix3Xf::Random(3, 2);
  map.add(b, {1, 1}, {0.6f, 0.7f}, 3);
  map.add(b, {0, 0}, {0.6f, 0.7f}, 4);  // keeps nothing
  ASSERT_EQ(map.size(), 5u);
  map.write(std::vector<std::filesystem::path>{dir / "m.pcd", dir / "m.ply"});
  const Eigen::Matrix3Xf p = map.points();
  for (const char* f : {"m.pcd", "m.ply"}) {
    const Scan r = read_cloud(dir / f);
    ASSERT_EQ(r.size(), 5u) << f;
    EXPECT_FALSE(r.has_intensity()) << f;
    EXPECT_EQ(r.points, p) << f;
    EXPECT_EQ(r.points.col(0), a.points.col(0)) << f;
    EXPECT_EQ(r.points.col(4), b.points.col(1)) << f;
  }
  // The score and scan fields, by the PCD's own bytes: the last row is 0.7, scan 3.
  std::ifstream in(dir / "m.pcd", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("FIELDS x y z score scan"), std::string::npos);
  float last[2];
  std::memcpy(last, bytes.data() + bytes.size() - 8, 8);
  EXPECT_EQ(last[0], 0.7f);
  EXPECT_EQ(last[1], 3.0f);
}

}  // namespace
}  // namespace cleanmap
