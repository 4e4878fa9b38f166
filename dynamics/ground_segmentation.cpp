#include "dynamics/ground_segmentation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <utility>
#include <string>

#include "io/error.hpp"
#include "geometry/voxel_key.hpp"

namespace cleanmap {

void validate(const GroundConfig& c) {
  auto bad = [](const std::string& what) { throw Error("ground: " + what); };
  if (!std::isfinite(c.cell) || !(c.cell > 0)) bad("ground_cell must be positive");
  if (!std::isfinite(c.height) || !(c.height > 0)) bad("ground_height must be positive");
  if (!std::isfinite(c.max_slope) || !(c.max_slope >= 0)) bad("ground_max_slope must be >= 0");
  if (!std::isfinite(c.reach) || !(c.reach >= 0)) bad("ground_reach must be >= 0");
  if (!std::isfinite(c.floor_band) || !(c.floor_band >= 0) || c.floor_band > c.height) {
    bad("ground_floor_band must be in [0, ground_height]");
  }
}

namespace {

using CellMap = tsl::robin_map<VoxelKey, float, VoxelKeyHash>;

// Each cell's lowest point, without returns from below the ground. Multipath returns (mirror
// images of the street in windows and wet road, SemanticKITTI's "outlier" class) lie metres
// under the road, several to a cell and in the same place scan after scan (07: three points
// 3.7 m down in one cell); as a floor they sank every cell within `reach`, and the road, the
// kerb and a pedestrian's feet joined one non-ground object (07's precision 0.49). A point is
// below the ground when it lies deeper under the median floor of its 3x3 block than a walkable
// slope across the block plus a ground band explain. (Taking a cell's 2nd or 3rd lowest point
// instead did not stop them, and cost SemanticKITTI 01 a tenth of its recall.)
// `lowest_allowed_of`, when given (a memory's floors are to meet the same rule), receives every
// cell's bound (its block's median floor less that drop).
CellMap cell_lowest(const Eigen::Matrix3Xf& points, const std::vector<VoxelKey>& key, const GroundConfig& c,
                    CellMap* lowest_allowed_of) {
  CellMap low;
  low.reserve(key.size() / 16 + 1);
  auto add = [&](std::size_t i) {
    const float z = points(2, static_cast<Eigen::Index>(i));
    auto [it, fresh] = low.try_emplace(key[i], z);
    if (!fresh) it.value() = std::min(it->second, z);
  };
  for (std::size_t i = 0; i < key.size(); ++i) add(i);
  const auto drop = static_cast<float>(2.0 * c.max_slope * c.cell + c.height);
  CellMap bound;  // lowest admissible point, for cells holding points below it
  for (const auto& [k, z] : low) {
    std::array<float, 9> block{};
    int m = 0;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const auto it = low.find(VoxelKey{k.x + dx, k.y + dy, 0});
        if (it != low.end()) block[m++] = it->second;
      }
    }
    std::nth_element(block.begin(), block.begin() + m / 2, block.begin() + m);
    const float lowest_allowed = block[m / 2] - drop;
    if (lowest_allowed_of != nullptr) lowest_allowed_of->emplace(k, lowest_allowed);
    if (z < lowest_allowed) bound.emplace(k, lowest_allowed);
  }
  if (bound.empty()) return low;
  // Such cells keep their lowest admissible point, or, when all their points are below, their
  // block's median floor: where the surface around them lies. The bound itself (0.85 m under
  // it with the default slope and band) was the floor of every cell in its 3x3 block: on KITTI
  // 00 one return 9 m under the road, alone in its cell, lifted the road around it 0.85 m off
  // the floor, and the road joined a passing motorcyclist's object (51 false dynamic points
  // in scan 2 beside its 70).
  for (const auto& [k, b] : bound) low[k] = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < key.size(); ++i) {
    const auto it = bound.find(key[i]);
    if (it != bound.end() && points(2, static_cast<Eigen::Index>(i)) >= it->second) add(i);
  }
  for (const auto& [k, b] : bound) {
    if (std::isinf(low[k])) low[k] = b + drop;
  }
  return low;
}

// Neighbour offsets with the rise allowed to reach them: 0 in the 3x3 block (always searched,
// whatever the reach), max_slope * distance beyond it.
std::vector<std::pair<VoxelKey, float>> floor_neighbours(const GroundConfig& c) {
  const int r = std::max(1, static_cast<int>(std::floor(c.reach / c.cell)));
  std::vector<std::pair<VoxelKey, float>> around;
  for (int dx = -r; dx <= r; ++dx) {
    for (int dy = -r; dy <= r; ++dy) {
      const double d = c.cell * std::hypot(dx, dy);
      if (std::abs(dx) <= 1 && std::abs(dy) <= 1) {
        around.push_back({{dx, dy, 0}, 0.0f});
      } else if (d <= c.reach + 1e-9) {
        around.push_back({{dx, dy, 0}, static_cast<float>(c.max_slope * d)});
      }
    }
  }
  return around;
}

// Forgets what is older than the memory's span, then lowers this scan's cells to what the
// remaining scans saw there (within this scan's `lowest_allowed`), and remembers this scan's
// lowest points.
void merge_memory(CellMap& lowest, const CellMap& lowest_allowed, GroundMemory& m) {
  const std::size_t now = m.now++;
  for (auto it = m.lowest.begin(); it != m.lowest.end();) {
    it = now - it->second.scan >= m.scans ? m.lowest.erase(it) : std::next(it);
  }
  for (auto it = lowest.begin(); it != lowest.end(); ++it) {
    auto [mem, fresh] = m.lowest.try_emplace(it->first, GroundMemory::Lowest{it->second, now});
    if (fresh) continue;
    const float remembered = mem->second.z;
    if (remembered >= it->second) {
      mem.value() = {it->second, now};  // as low or lower: seen again now
    } else if (remembered < lowest_allowed.find(it->first)->second) {
      // Deeper under this scan's own block floor than a slope and the band explain: a mirror
      // image that filled an earlier scan's block (so that scan took it for floor), not a
      // floor a car now hides. Forgotten.
      mem.value() = {it->second, now};
    } else {
      it.value() = remembered;  // a lower floor seen recently
    }
  }
}

std::vector<VoxelKey> cell_keys(const Eigen::Matrix3Xf& points, const GroundConfig& c) {
  const double inv = 1.0 / c.cell;
  std::vector<VoxelKey> key(static_cast<std::size_t>(points.cols()));
  for (std::size_t i = 0; i < key.size(); ++i) {
    const auto p = points.col(static_cast<Eigen::Index>(i));
    key[i] = {static_cast<std::int32_t>(std::floor(p.x() * inv)),
              static_cast<std::int32_t>(std::floor(p.y() * inv)), 0};
  }
  return key;
}

// Each point's height above its cell's floor, from the cells' lowest points (`lowest`: this
// scan's; `elsewhere(cell, k, z)`: cell k, which this scan did not see, as a neighbour of
// `cell`, true when known).
// A cell's floor is the lowest point of its 3x3 block, unless that floor floats above the
// slope-limited lower envelope of the lowest points within `reach` (min over cells n of
// lowest(n) + max_slope * distance, a morphological opening with a cone as in progressive
// morphological ground filters): then it is a roof, and the envelope is its floor. The
// envelope alone lifts the floor beside objects by max_slope * cell (a car's sill became
// ground: SemanticKITTI 01 recall 0.75 -> 0.60).
template <class Elsewhere>
std::vector<float> heights_over(const Eigen::Matrix3Xf& points, const std::vector<VoxelKey>& key,
                                const GroundConfig& c, const CellMap& lowest, Elsewhere elsewhere) {
  const auto around = floor_neighbours(c);
  CellMap ground_z;
  ground_z.reserve(lowest.size());
  for (const auto& [k, z] : lowest) {
    float g = z;
    for (const auto& [off, rise] : around) {
      const VoxelKey n{k.x + off.x, k.y + off.y, 0};
      float other = 0.0f;
      if (const auto it = lowest.find(n); it != lowest.end()) {
        g = std::min(g, it->second + rise);
      } else if (elsewhere(k, n, other)) {
        g = std::min(g, other + rise);
      }
    }
    ground_z.emplace(k, g);
  }
  std::vector<float> height(key.size());
  for (std::size_t i = 0; i < key.size(); ++i) {
    height[i] = points(2, static_cast<Eigen::Index>(i)) - ground_z.find(key[i])->second;
  }
  return height;
}

std::vector<std::uint8_t> below(const std::vector<float>& h, const GroundConfig& c) {
  std::vector<std::uint8_t> ground(h.size());
  const auto band = static_cast<float>(c.height);
  for (std::size_t i = 0; i < h.size(); ++i) ground[i] = h[i] < band ? 1 : 0;
  return ground;
}

}  // namespace

std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, const GroundConfig& c,
                                         GroundMemory* memory) {
  return below(ground_heights(points, c, memory), c);
}

std::vector<float> ground_heights(const Eigen::Matrix3Xf& points, const GroundConfig& c, GroundMemory* memory) {
  const auto key = cell_keys(points, c);
  const bool remembers = memory != nullptr && memory->scans > 0;
  CellMap lowest_allowed;
  CellMap lowest = cell_lowest(points, key, c, remembers ? &lowest_allowed : nullptr);
  if (remembers) merge_memory(lowest, lowest_allowed, *memory);
  // Neighbours come from the memory too when it holds cells this scan did not see.
  return heights_over(points, key, c, lowest, [&](const VoxelKey&, const VoxelKey& k, float& z) {
    if (memory == nullptr) return false;
    const auto it = memory->lowest.find(k);
    if (it == memory->lowest.end()) return false;
    z = it->second.z;
    return true;
  });
}

void add_to_floor(const Eigen::Matrix3Xf& points, const GroundConfig& c, LogFloor& floor) {
  const CellMap lowest = cell_lowest(points, cell_keys(points, c), c, nullptr);
  for (const auto& [k, z] : lowest) {
    auto [it, fresh] = floor.try_emplace(k, z);
    if (!fresh && z < it->second) it.value() = z;
  }
}

std::vector<std::uint8_t> segment_ground(const Eigen::Matrix3Xf& points, const GroundConfig& c,
                                         const LogFloor& floor) {
  const auto key = cell_keys(points, c);
  CellMap lowest_allowed;
  CellMap lowest = cell_lowest(points, key, c, &lowest_allowed);
  // The log's lowest point counts where this scan's block says it may be floor: in the cell
  // itself, and for a neighbour this scan did not see, under the cell it floors.
  auto admissible = [&](const VoxelKey& cell, const VoxelKey& k, float& z) {
    const auto f = floor.find(k);
    if (f == floor.end() || f->second < lowest_allowed.find(cell)->second) return false;
    z = f->second;
    return true;
  };
  for (auto it = lowest.begin(); it != lowest.end(); ++it) {
    float z = 0.0f;
    if (admissible(it->first, it->first, z) && z < it->second) it.value() = z;
  }
  return below(heights_over(points, key, c, lowest, admissible), c);
}

}  // namespace cleanmap
