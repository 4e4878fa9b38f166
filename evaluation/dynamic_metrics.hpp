#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace cleanmap {

// Confusion counts of the moving class, the moving-object-segmentation convention (the class of
// interest is "moving"; IoU = TP / (TP + FP + FN)).
struct MovingConfusion {
  std::size_t tp = 0, fp = 0, fn = 0, tn = 0;
  std::size_t unscored = 0;  // predictions with no decision, counted as static

  MovingConfusion& operator+=(const MovingConfusion& o);
  double iou() const;        // NaN when there is nothing moving in truth or prediction
  double precision() const;  // NaN with no predicted moving point
  double recall() const;     // NaN with no moving point in the truth
};

// Adds one point: predicted moving?, truly moving?, had a decision?
inline void count(MovingConfusion& c, bool predicted, bool truth, bool scored = true) {
  if (!scored) ++c.unscored;
  if (predicted && truth) ++c.tp;
  else if (predicted) ++c.fp;
  else if (truth) ++c.fn;
  else ++c.tn;
}

}  // namespace cleanmap
